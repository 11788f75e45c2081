// The mapping of a spec onto LAMMPS's granular models (model/lammps.hpp): each LAMMPS coefficient
// gives back LIGGGHTS's effective quantity, computed LAMMPS's way from what the deck passes.
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/stack.hpp>

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

model::Material steel() { return {"steel", 8000.0, 193e9, 0.3}; }
model::Material teflon() { return {"teflon", 2200.0, 1.46e9, 0.46}; }

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
    const auto pair = model::lammps_contact(a, b, 1.0, 0.0, false);
    EXPECT_LE(relative(lammps_e_star(pair.youngs_modulus, pair.poisson_ratio), model::effective_youngs_modulus(a, b)), 4e-16);
    EXPECT_LE(relative(lammps_g_star(pair.youngs_modulus, pair.poisson_ratio), model::effective_shear_modulus(a, b)), 4e-16);
    EXPECT_LE(relative(pair.tangential_stiffness, 8.0 * model::effective_shear_modulus(a, b)), 1e-16);
    const auto wall = model::lammps_contact(a, b, 1.0, 0.0, true);
    EXPECT_LE(relative(lammps_wall_e_star(wall.youngs_modulus, wall.poisson_ratio), model::effective_youngs_modulus(a, b)),
              4e-16);
  }
  const auto same = model::lammps_contact(steel(), steel(), 1.0, 0.0, false);
  EXPECT_EQ(same.youngs_modulus, 193e9);
  EXPECT_EQ(same.poisson_ratio, 0.3);
  // LIGGGHTS's gamma_t / gamma_n = sqrt(S_t / S_n) = sqrt(4 G* / Y*).
  const auto st = model::lammps_contact(steel(), teflon(), 0.5, 0.3, false);
  EXPECT_LE(relative(st.tangential_damping, std::sqrt(4.0 * model::effective_shear_modulus(steel(), teflon()) /
                                                      model::effective_youngs_modulus(steel(), teflon()))),
            4e-16);
}

TEST(Lammps, ContactWordsNameTheModels) {
  EXPECT_EQ(model::lammps_contact_words(model::lammps_contact(steel(), steel(), 1.0, 0.0, false)),
            "hertz/material 193000000000 0 0.29999999999999999 damping viscoelastic tangential linear_nohistory 0 0");
  const auto words = model::lammps_contact_words(model::lammps_contact(steel(), steel(), 0.9, 0.25, false));
  EXPECT_NE(words.find(" damping tsuji tangential mindlin "), std::string::npos) << words;
  EXPECT_EQ(words.find("NULL"), std::string::npos) << words;  // k_t given: this LAMMPS's wall NULL is not 8 G*
}

// What the mapping cannot express is refused by name; the study's models map.
TEST(Lammps, UnmappableSpecsAreRefusedByName) {
  model::StackSpec spec;
  EXPECT_EQ(model::lammps_unmappable(spec), "");
  spec.restitution.value = 0.9;
  spec.friction.value = 0.3;
  spec.dump_format = model::DumpFormat::binary;
  EXPECT_EQ(model::lammps_unmappable(spec), "");
  auto hooke = spec;
  hooke.normal_model = model::NormalModel::hooke;
  EXPECT_NE(model::lammps_unmappable(hooke).find("normal_model = 'hooke'"), std::string::npos);
  auto rolling = spec;
  rolling.rolling_model = model::RollingModel::epsd2;
  EXPECT_NE(model::lammps_unmappable(rolling).find("epsd2"), std::string::npos);
  auto viscous = spec;
  viscous.tangential_model = model::TangentialModel::no_history;
  EXPECT_NE(model::lammps_unmappable(viscous).find("no_history"), std::string::npos);
  auto nearly_elastic = spec;
  nearly_elastic.restitution.set("steel", "steel", 0.9999);
  EXPECT_NE(model::lammps_unmappable(nearly_elastic).find("restitution 0.9999"), std::string::npos);
  auto per_rank = spec;
  per_rank.dump_files = model::DumpFiles::per_rank;
  EXPECT_NE(model::lammps_unmappable(per_rank).find("per_rank"), std::string::npos);
}

// The deck: every type pair set (LAMMPS would mix an unset one its own way), each wall one fix per
// atom type with spheres, the bottom wall's force summed over them; an unknown placeholder in a
// user's template is refused by name.
TEST(Lammps, DeckSetsEveryTypePairAndAWallFixPerType) {
  formats::Manifest m;
  m.case_name = "c";
  m.spec.blocks = 3;
  m.spec.rows = 2;
  m.spec.materials = {"steel", "teflon", "steel"};
  m.spec.bottom = model::Boundary::wall;
  m.spec.sides = model::Boundary::wall;
  m.spec.restitution.value = 0.8;
  const auto stack = model::Stack::build(m.spec);
  m.files = generator::case_files(stack);
  const auto res = model::resolve(stack);
  const auto deck = generator::lammps_deck(stack, res, m.files, m.case_name, generator::default_lammps_template(),
                                           "templates/in.lammps.tmpl");
  // Types: 3 blocks, the striker, the wall: 5 types, 15 pairs.
  EXPECT_EQ(count(deck, "\npair_coeff "), 15u) << deck;
  EXPECT_EQ(count(deck, " damping tsuji"), 15u + 3u * 4u);  // the pairs and 3 walls x 4 sphere types
  EXPECT_EQ(count(deck, "wall/gran granular"), 12u);
  EXPECT_NE(deck.find("variable        fwb equal c_fwb1+c_fwb2+c_fwb3+c_fwb4"), std::string::npos) << deck;
  EXPECT_THROW(generator::lammps_deck(stack, res, m.files, m.case_name, "{{no_such_thing}}", "mine.tmpl"), std::runtime_error);
}
