// The mapping of a spec onto LAMMPS's granular models (model/lammps.hpp): each LAMMPS coefficient
// gives back LIGGGHTS's effective quantity, computed LAMMPS's way from what the deck passes.
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace granstack;

namespace {

double relative(double a, double b) { return std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

// What LAMMPS 29 Sep 2021 computes from a pair_coeff's (E, nu) (pair_granular.cpp's
// mix_stiffnessE and mix_stiffnessG with both sides given the same values), and fix wall/gran's E*.
double lammps_e_star(double e, double nu) { return 1 / ((1 - nu * nu) / e + (1 - nu * nu) / e); }
double lammps_g_star(double e, double nu) { return 1 / (2 * (2 - nu) * (1 + nu) / e + 2 * (2 - nu) * (1 + nu) / e); }
double lammps_wall_e_star(double e, double nu) { return e / (2 * (1 - nu)); }

const model::LammpsRules& here() { return model::lammps_rules_run_here(); }

model::Material steel() { return {"steel", 8000.0, 193e9, 0.3, {}}; }
model::Material teflon() { return {"teflon", 2200.0, 1.46e9, 0.46, {}}; }

// A case of three blocks of 2 rows, steel over Teflon over steel, e = 0.8, on a bottom wall (and
// between side walls with `sides`), with its files named.
formats::Manifest steel_teflon_steel(bool sides) {
  formats::Manifest m;
  m.case_name = "c";
  m.spec.blocks = 3;
  m.spec.rows = 2;
  m.spec.materials = {"steel", "teflon", "steel"};
  m.spec.bottom = model::Boundary::wall;
  if (sides) m.spec.sides = model::Boundary::wall;
  m.spec.restitution.value = 0.8;
  m.files = generator::case_files(model::Stack::build(m.spec));
  return m;
}

std::size_t count(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

}  // namespace

// Tsuji's alpha at the chosen e' is LIGGGHTS's damping factor sqrt(5) |beta(e)| to within one ulp of
// the polynomial's largest term (27.467 e^4: 3.6e-15), the round-off LAMMPS's own evaluation of
// alpha carries (near e' = 1 alpha is 1e-3 and its terms cancel), over the mappable range; and
// alpha falls monotonically on [0, 1], so e' is unique.
TEST(Lammps, TsujiRestitutionGivesLiggghtsDamping) {
  for (const double e : {0.12, 0.2, 0.5, 0.6, 0.9, 0.95, 0.99, 0.999, 0.9995}) {
    const double ep = model::lammps_tsuji_restitution(e);
    ASSERT_GE(ep, 0.0) << e;
    ASSERT_LE(ep, 1.0) << e;
    const double want = std::sqrt(5.0) * std::abs(model::restitution_beta(e));
    EXPECT_LE(std::abs(model::tsuji_alpha(ep) - want), std::nextafter(27.467, 28.0) - 27.467) << "e = " << e << ", e' = " << ep;
  }
  double previous = model::tsuji_alpha(0.0);
  for (int k = 1; k <= 1000; ++k) {
    const double a = model::tsuji_alpha(k / 1000.0);
    EXPECT_LT(a, previous) << k;
    previous = a;
  }
  // Outside the range tsuji's alpha spans: no e' (alpha(1) = 3e-4 > 0, alpha(0) = 1.2728). The
  // range the refusal and docs state, 0.1137 to 0.99957, lies within the mappable one and reaches
  // its ends to their last stated digit.
  EXPECT_NEAR(model::tsuji_alpha(1.0), 3e-4, std::nextafter(27.467, 28.0) - 27.467);  // the coefficients sum to 3e-4
  EXPECT_EQ(model::tsuji_alpha(0.0), 1.2728);
  EXPECT_LT(model::lammps_tsuji_restitution(0.9999), 0.0);
  EXPECT_LT(model::lammps_tsuji_restitution(0.06), 0.0);
  EXPECT_GE(model::lammps_tsuji_restitution(0.1137), 0.0);
  EXPECT_LT(model::lammps_tsuji_restitution(0.1136), 0.0);
  EXPECT_GE(model::lammps_tsuji_restitution(0.99957), 0.0);
  EXPECT_LT(model::lammps_tsuji_restitution(0.99958), 0.0);
}

// A pair of two materials: the (E', nu') passed give LAMMPS's E* and G* equal to LIGGGHTS's; a
// wall's E' gives fix wall/gran's own E* form the pair's E*; one material passes its own values.
TEST(Lammps, ModuliGiveLiggghtsEffectiveModuli) {
  for (const auto& [a, b] : {std::pair{steel(), teflon()}, std::pair{teflon(), steel()}, std::pair{steel(), steel()}}) {
    const auto pair = model::lammps_contact(a, b, 1.0, 0.0, false, here());
    EXPECT_LE(relative(lammps_e_star(pair.youngs_modulus, pair.poisson_ratio), model::effective_youngs_modulus(a, b)), 4e-16);
    EXPECT_LE(relative(lammps_g_star(pair.youngs_modulus, pair.poisson_ratio), model::effective_shear_modulus(a, b)), 4e-16);
    EXPECT_LE(relative(pair.tangential_stiffness, 8.0 * model::effective_shear_modulus(a, b)), 1e-16);
    const auto wall = model::lammps_contact(a, b, 1.0, 0.0, true, here());
    EXPECT_LE(relative(lammps_wall_e_star(wall.youngs_modulus, wall.poisson_ratio), model::effective_youngs_modulus(a, b)),
              4e-16);
  }
  const auto same = model::lammps_contact(steel(), steel(), 1.0, 0.0, false, here());
  EXPECT_EQ(same.youngs_modulus, 193e9);
  EXPECT_EQ(same.poisson_ratio, 0.3);
  // LIGGGHTS's gamma_t / gamma_n = sqrt(S_t / S_n) = sqrt(4 G* / Y*).
  const auto st = model::lammps_contact(steel(), teflon(), 0.5, 0.3, false, here());
  EXPECT_LE(relative(st.tangential_damping, std::sqrt(4.0 * model::effective_shear_modulus(steel(), teflon()) /
                                                      model::effective_youngs_modulus(steel(), teflon()))),
            4e-16);
}

TEST(Lammps, ContactWordsNameTheModels) {
  EXPECT_EQ(model::lammps_contact_words(model::lammps_contact(steel(), steel(), 1.0, 0.0, false, here()), here()),
            "hertz/material 193000000000 0 0.29999999999999999 damping viscoelastic tangential linear_nohistory 0 0");
  const auto words = model::lammps_contact_words(model::lammps_contact(steel(), steel(), 0.9, 0.25, false, here()), here());
  EXPECT_NE(words.find(" damping tsuji tangential mindlin "), std::string::npos) << words;
  const auto rescale = model::lammps_contact_words(model::lammps_contact(steel(), steel(), 0.9, 0.25, false, here()), here(),
                                                   model::TangentialModel::mindlin_rescale);
  EXPECT_EQ(rescale.substr(0, rescale.find(" tangential ")), words.substr(0, words.find(" tangential ")));
  EXPECT_EQ(rescale.substr(rescale.find(" tangential ")),
            " tangential mindlin_rescale" + words.substr(words.find(" tangential ") + std::string(" tangential mindlin").size()));
  EXPECT_EQ(words.find("NULL"), std::string::npos) << words;  // k_t given: this LAMMPS's wall NULL is not 8 G*
}

// What the mapping cannot express is refused by name; the study's models map.
TEST(Lammps, UnmappableSpecsAreRefusedByName) {
  model::StackSpec spec;
  EXPECT_EQ(model::lammps_unmappable(spec, here()), "");
  spec.restitution.value = 0.9;
  spec.friction.value = 0.3;
  spec.dump_format = model::DumpFormat::binary;
  EXPECT_EQ(model::lammps_unmappable(spec, here()), "");
  auto hooke = spec;
  hooke.normal_model = model::NormalModel::hooke;
  EXPECT_NE(model::lammps_unmappable(hooke, here()).find("normal_model = 'hooke'"), std::string::npos);
  auto rolling = spec;
  rolling.rolling_model = model::RollingModel::epsd2;
  EXPECT_NE(model::lammps_unmappable(rolling, here()).find("epsd2"), std::string::npos);
  rolling.rolling_model = model::RollingModel::cdt;
  EXPECT_NE(model::lammps_unmappable(rolling, here()).find("rolling_model = 'cdt' has no counterpart"), std::string::npos);
  auto viscous = spec;
  viscous.tangential_model = model::TangentialModel::no_history;
  EXPECT_NE(model::lammps_unmappable(viscous, here()).find("no_history"), std::string::npos);
  auto nearly_elastic = spec;
  nearly_elastic.restitution.set("steel", "steel", 0.9999);
  EXPECT_NE(model::lammps_unmappable(nearly_elastic, here()).find("restitution 0.9999"), std::string::npos);
  auto per_rank = spec;
  per_rank.dump_files = model::DumpFiles::per_rank;
  EXPECT_NE(model::lammps_unmappable(per_rank, here()).find("per_rank"), std::string::npos);
}

// The deck: every type pair set (LAMMPS would mix an unset one its own way), each wall one fix per
// atom type with spheres, the bottom wall's force summed over them; an unknown placeholder in a
// user's template is refused by name.
TEST(Lammps, DeckSetsEveryTypePairAndAWallFixPerType) {
  const auto m = steel_teflon_steel(true);
  const auto stack = model::Stack::build(m.spec);
  const auto res = model::resolve(stack);
  const auto deck = generator::lammps_deck(stack, res, m.files, m.case_name, generator::default_lammps_template(),
                                           "templates/in.lammps.tmpl", here());
  // Types: 3 blocks, the striker, the wall: 5 types, 15 pairs.
  EXPECT_EQ(count(deck, "\npair_coeff "), 15u) << deck;
  EXPECT_EQ(count(deck, " damping tsuji tangential"), 15u + 3u * 4u);  // the pairs and 3 walls x 4 sphere types
  EXPECT_EQ(count(deck, "wall/gran granular"), 12u);
  EXPECT_NE(deck.find("variable        fwb equal c_fwb1+c_fwb2+c_fwb3+c_fwb4"), std::string::npos) << deck;
  EXPECT_THROW(generator::lammps_deck(stack, res, m.files, m.case_name, "{{no_such_thing}}", "mine.tmpl", here()), std::runtime_error);
}

// The version `lmp -h` reports chooses the rules: Debian 12's (29 Sep 2021 - Update 2) the family
// run here, a release of the rewrite with coeff_restitution the other family; a release between
// them, one before, one after the newest read, or a banner without a date, none.
TEST(Lammps, TheReportedVersionChoosesTheRules) {
  const auto banner = [](const std::string& v) {
    return "\nLarge-scale Atomic/Molecular Massively Parallel Simulator - " + v + "\n\nUsage example: lmp -var t 300\n";
  };
  const auto debian = model::parse_lammps_version(banner("29 Sep 2021 - Update 2"));
  ASSERT_TRUE(debian);
  EXPECT_EQ(debian->year, 2021);
  EXPECT_EQ(debian->month, 9);
  EXPECT_EQ(debian->day, 29);
  EXPECT_EQ(debian->update, 2);
  EXPECT_EQ(debian->text, "29 Sep 2021 - Update 2");
  ASSERT_EQ(model::lammps_rules_for(*debian), &model::lammps_rules_run_here());
  EXPECT_EQ(model::lammps_rules_run_here().wall, model::LammpsWallModulus::one_minus_nu);
  EXPECT_EQ(model::lammps_rules_run_here().damping, model::LammpsDamping::tsuji_match);
  EXPECT_TRUE(model::lammps_rules_run_here().run_here);
  const auto stable = model::parse_lammps_version(banner("29 Aug 2024 - Update 1"));
  ASSERT_TRUE(stable);
  const auto* rewrite = model::lammps_rules_for(*stable);
  ASSERT_NE(rewrite, nullptr);
  for (const char* inside : {"27 Jun 2024", "28 Jun 2024", "1 Jul 2025", "22 Jul 2025"}) {
    EXPECT_EQ(model::lammps_rules_for(*model::parse_lammps_version(banner(inside))), rewrite) << inside;
  }
  EXPECT_EQ(rewrite->wall, model::LammpsWallModulus::one_minus_nu_squared);
  EXPECT_EQ(rewrite->damping, model::LammpsDamping::coeff_restitution);
  EXPECT_FALSE(rewrite->run_here);
  // Days in a bound's own month (#65: only other months were tried, so a rule that read the month
  // and not the day would pass): the day before a family's first release, and after its last.
  for (const char* unknown : {"2 Aug 2023", "7 Feb 2024", "23 Jun 2022", "29 Oct 2020", "11 Feb 2026", "1 Sep 2021",
                              "28 Sep 2021", "30 Sep 2021", "26 Jun 2024", "23 Jul 2025", "31 Jul 2025"}) {
    const auto v = model::parse_lammps_version(banner(unknown));
    ASSERT_TRUE(v) << unknown;
    EXPECT_EQ(model::lammps_rules_for(*v), nullptr) << unknown;
  }
  EXPECT_FALSE(model::parse_lammps_version("LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)"));
  EXPECT_FALSE(model::parse_lammps_version(banner("Development")));
  EXPECT_FALSE(model::parse_lammps_version(banner("31 Foo 2024")));
  const auto known = model::known_lammps_versions();
  EXPECT_NE(known.find("29 Sep 2021 (every update), run against a real binary"), std::string::npos) << known;
  EXPECT_NE(known.find("27 Jun 2024 to 22 Jul 2025, written from its source, not run"), std::string::npos) << known;
}

// The rewrite's walls form E* as pairs do (gran_sub_mod.cpp's mix_stiffnessE_wall: E / (2 (1 -
// nu^2))): its wall E' gives the pair's E*, and the 2021 wall's E' on such a LAMMPS would be (1 +
// nu) too stiff, the 2021 LAMMPS's E' too soft on it by 1/(1 + nu) (the 23 % on steel's
// output). Its damping is coeff_restitution with e itself, whose coefficient (LAMMPS's sqrt(3/2) 2
// sqrt(5/6) |ln e| / sqrt(pi^2 + ln^2 e)) is LIGGGHTS's sqrt(5) |beta(e)| to round-off, over the
// whole range (no tsuji limits).
TEST(Lammps, TheRewritesWallsAndDampingMapAsItsSourceSays) {
  const auto* rewrite = model::lammps_rules_for(*model::parse_lammps_version(
      "Large-scale Atomic/Molecular Massively Parallel Simulator - 22 Jul 2025\n"));
  ASSERT_NE(rewrite, nullptr);
  const auto rewrite_wall_e_star = [](double e, double nu) { return e / (2 * (1 - nu * nu)); };
  for (const auto& [a, b] : {std::pair{steel(), teflon()}, std::pair{teflon(), steel()}, std::pair{steel(), steel()}}) {
    const auto wall = model::lammps_contact(a, b, 1.0, 0.0, true, *rewrite);
    EXPECT_LE(relative(rewrite_wall_e_star(wall.youngs_modulus, wall.poisson_ratio), model::effective_youngs_modulus(a, b)),
              4e-16);
    const auto old = model::lammps_contact(a, b, 1.0, 0.0, true, here());
    EXPECT_LE(relative(rewrite_wall_e_star(old.youngs_modulus, old.poisson_ratio) * (1 + old.poisson_ratio),
                       model::effective_youngs_modulus(a, b)),
              4e-16);
  }
  EXPECT_EQ(model::lammps_contact(steel(), steel(), 1.0, 0.0, true, *rewrite).youngs_modulus, 193e9);
  for (const double e : {0.05, 0.5, 0.9, 0.9999}) {
    const auto c = model::lammps_contact(steel(), steel(), e, 0.0, false, *rewrite);
    EXPECT_EQ(c.tsuji_restitution, e);
    const double l = std::log(e);
    const double lammps = -1.22474487139158894067 * 1.82574185835055380345 * l / std::sqrt(M_PI * M_PI + l * l);
    EXPECT_LE(relative(lammps, std::sqrt(5.0) * std::abs(model::restitution_beta(e))), 4e-16) << e;
    const auto words = model::lammps_contact_words(c, *rewrite);
    EXPECT_NE(words.find(fmt::format("hertz/material 193000000000 {:.17g} 0.29999999999999999 damping coeff_restitution", e)),
              std::string::npos)
        << words;
  }
  model::StackSpec spec;
  spec.restitution.value = 0.9999;
  EXPECT_EQ(model::lammps_unmappable(spec, *rewrite), "");
  EXPECT_NE(model::lammps_unmappable(spec, here()).find("restitution 0.9999"), std::string::npos);
}

// Every pair_coeff line carries its own pair's words (a deck that gave every pair the diagonal's
// would run teflon against steel as steel against steel), and the deck says what each damping
// coefficient stands for and, with walls and tsuji, where this LAMMPS changes its own damping.
TEST(Lammps, EachPairCoeffIsItsOwnPairsAndTheDeckSaysWhatItMapped) {
  const auto m = steel_teflon_steel(false);
  const auto stack = model::Stack::build(m.spec);
  const auto deck = generator::lammps_deck(stack, model::resolve(stack), m.files, m.case_name,
                                           generator::default_lammps_template(), "templates/in.lammps.tmpl", here());
  const auto types = stack.type_materials();
  const auto lib = m.spec.material_library();
  for (std::size_t i = 0; i < types.size(); ++i) {
    for (std::size_t j = i; j < types.size(); ++j) {
      const auto words = model::lammps_contact_words(
          model::lammps_contact(lib.at(types[i]), lib.at(types[j]), 0.8, 0.0, false, here()), here());
      EXPECT_NE(deck.find(fmt::format("pair_coeff      {} {} {}\n", i + 1, j + 1, words)), std::string::npos)
          << types[i] << "-" << types[j];
    }
  }
  EXPECT_NE(deck.find(fmt::format("# Restitution 0.8: damping tsuji with e' = {:.17g}", model::lammps_tsuji_restitution(0.8))),
            std::string::npos)
      << deck;
  EXPECT_NE(deck.find("# Mapped for LAMMPS 29 Sep 2021 (checked against a real binary)"), std::string::npos);
  EXPECT_NE(deck.find("converts its tsuji coefficient in place each time a run does its setup"), std::string::npos);
  EXPECT_NE(deck.find("Run by\n# hand, LAMMPS chooses"), std::string::npos);
  EXPECT_EQ(deck.find("LIGGGHTS chooses"), std::string::npos);
  EXPECT_NE(deck.find("thermo_style    custom step atoms ke c_gs_erot cpu"), std::string::npos);
  // 5 types (3 blocks, the striker, the wall): 15 pairs; the bottom wall, one fix per sphere type.
  std::size_t pairs = 0, walls = 0;
  for (std::size_t at = 0; (at = deck.find('\n', at)) != std::string::npos; ++at) {
    pairs += deck.compare(at + 1, 10, "pair_coeff") == 0 ? 1 : 0;
    const auto end = deck.find('\n', at + 1);
    walls += deck.compare(at + 1, 3, "fix") == 0 && deck.substr(at + 1, end - at - 1).find(" wall/gran ") != std::string::npos;
  }
  EXPECT_EQ(pairs, 15u);
  EXPECT_EQ(walls, 4u);
}
