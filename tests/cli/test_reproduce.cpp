// `granstack reproduce --quick` end to end on the real LIGGGHTS: the numbers against the
// catalogue's bands and against physics computed here, reuse of finished cases, refusals, and the
// HTML report opened in a real headless browser.
#include "../support/program.hpp"
#include "../support/scratch.hpp"

#include <granstack/os/process.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <csignal>
#include <map>
#include <thread>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace granstack;

namespace {

using Result = test::ProgramResult;
using test::read_bytes;

const fs::path& work() {
  static const fs::path dir = fs::path(GRANSTACK_TEST_WORKDIR) / "reproduce";
  return dir;
}

// Runs a program from an argument vector, its stdout and stderr into a file.
Result run(std::vector<std::string> argv) { return test::run_program(std::move(argv), work() / "last_output.txt"); }

Result granstack(std::vector<std::string> args) {
  args.insert(args.begin(), GRANSTACK_EXE);
  return run(args);
}

// One quick reproduction shared by the tests (it is the expensive part). The HTML test runs in a
// process of its own (ctest's reproduce.html, which can then say skipped where Chromium is
// missing) on the reproduction the `reproduce` test made: GRANSTACK_QUICK_REPRODUCTION names it.
const fs::path& quick_dir() {
  static const fs::path dir = [] {
    const auto d = work() / "quick";
    if (std::getenv("GRANSTACK_QUICK_REPRODUCTION") != nullptr) {
      EXPECT_TRUE(fs::is_regular_file(d / "report.json")) << "the reproduce test made no reproduction in " << d;
      return d;
    }
    fs::remove_all(d);
    const auto r = granstack({"reproduce", "--quick", "-j", "2", "-o", d.string()});
    EXPECT_EQ(r.code, 0) << r.output;
    return d;
  }();
  return dir;
}

std::string fmt_key(const std::string& e, int nb) { return "output.e" + e + ".nb" + std::to_string(nb); }
std::string fmt_key_of(const std::string& series, int nb) { return "output." + series + ".nb" + std::to_string(nb); }

nlohmann::json report() { return nlohmann::json::parse(read_bytes(quick_dir() / "report.json")); }

const nlohmann::json& experiment(const nlohmann::json& report, const std::string& name) {
  for (const auto& e : report.at("experiments")) {
    if (e.at("name") == name) return e;
  }
  throw std::runtime_error("no experiment " + name);
}

TEST(Reproduce, QuickRunsOnLiggghtsAndEveryVerdictIsTheOneTheCatalogueExpects) {
  const auto j = report();
  EXPECT_EQ(j.at("engine"), "liggghts");
  EXPECT_EQ(j.at("failed_cases"), 0);
  int judged = 0;
  for (const auto& e : j.at("experiments")) {
    for (const auto& c : e.at("claims")) {
      if (c.at("verdict") == "not measured") continue;
      ++judged;
      // The value is within [low, high] exactly when the verdict says so, and that is what the
      // elastic model was measured to give (the catalogue's `expect`).
      const double v = c.at("value"), low = c.at("band")[0], high = c.at("band")[1];
      EXPECT_EQ(c.at("verdict") == "within", v >= low && v <= high) << c.dump();
      EXPECT_EQ(c.at("verdict"), c.at("expect")) << c.at("id") << ": " << c.at("statement") << " measured " << v;
    }
  }
  EXPECT_GE(judged, 20);  // fig2 (needed by fig4), fig3, scale (but the dt case), fig4, eq3
}

// The referee's third round (#48): every case table says where each case's blow stood when its run
// ended, and a claim of an experiment holding a case whose blow had not ended says so in the
// summary (eq3's striker of 3 and 4 top radii rattles on to the cap); the record's headline counts
// the verdicts settled with results in view from the record itself, geometry changes included; the
// units are written as units (µs, not us).
TEST(Reproduce, TheReportSaysWhichBlowsEndedAndCountsTheRecord) {
  const auto md = read_bytes(quick_dir() / "report.md");
  EXPECT_NE(md.find("| the blow |"), std::string::npos);
  EXPECT_NE(md.find("| ended at "), std::string::npos);
  EXPECT_NE(md.find("| NOT ENDED: "), std::string::npos);
  // The flag names the cases the claim's reading reads (#68.5): eq3.3 reads steel_rho4, eq3.1
  // steel_rho2, whose blow ended; the case table gives the whole reason, not its first 100 characters.
  EXPECT_NE(md.find("[it reads 1 case whose blow had not ended: steel_rho4]"), std::string::npos);
  const auto eq31 = md.find("| eq3.1 |");
  ASSERT_NE(eq31, std::string::npos);
  EXPECT_EQ(md.substr(eq31, md.find('\n', eq31) - eq31).find("whose blow had not ended"), std::string::npos);
  const auto rho4 = nlohmann::json::parse(read_bytes(quick_dir() / "eq3" / "steel_rho4" / "reduce" / "summary.json"));
  const auto why = rho4.at("blow_not_ended").get<std::string>();
  EXPECT_GT(why.size(), 100u);
  EXPECT_NE(md.find("| NOT ENDED: " + why + " |"), std::string::npos) << why;
  const std::regex headline(R"(Of the (\d+) claims here, (\d+) verdicts were settled with results in view: (\d+) by a change to the claim itself \([^)]*\), (\d+) by a change to the geometry or physics of its experiment's stack, or of the stack it reads, alone \(([^)]*)\), and (\d+) fixed first in the commit that first reported their results)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(md, m, headline)) << "no computed headline";
  EXPECT_EQ(std::stoi(m[2]), std::stoi(m[3]) + std::stoi(m[4]) + std::stoi(m[6]));
  EXPECT_GT(std::stoi(m[4]), 0);  // fig4's geometry changed with results known: its claims count
  EXPECT_EQ(md.find(" us)"), std::string::npos);
  EXPECT_EQ(md.find("this version"), std::string::npos);
}

// `granstack reproduce` of `experiments` on refsim (seconds) into work()/name: its report.md.
std::string refsim_report(const std::string& name, const std::vector<std::string>& experiments) {
  const auto d = work() / name;
  fs::remove_all(d);
  std::vector<std::string> args{"reproduce", "--engine", "refsim", "-j", "2", "-o", d.string()};
  args.insert(args.end(), experiments.begin(), experiments.end());
  const auto r = granstack(args);
  EXPECT_EQ(r.code, 0) << r.output;
  return fs::exists(d / "report.md") ? read_bytes(d / "report.md") : std::string();
}

// The referee's fourth round (#68.2): eq45 has no stack of its own and reads Fig. 2's, whose
// height changed from 8 to 24 rows with results known: its claims that no change of their own
// settled count with that change; and a statement rewritten with results known (mechanisms.3's,
// friction.3's) is in the record, counting as a change to the claim itself. On refsim (seconds).
TEST(Reproduce, TheRecordFollowsTheStackAClaimReadsAndItsStatement) {
  const auto md = refsim_report("record", {"eq45", "mechanisms"});
  const std::regex stack(R"(by a change to the geometry or physics of its experiment's stack, or of the stack it reads, alone \(([^)]*)\))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(md, m, stack)) << "no computed headline";
  EXPECT_NE(m[1].str().find("eq45.1"), std::string::npos) << m[1];
  EXPECT_NE(m[1].str().find("eq45.3"), std::string::npos) << m[1];
  const std::regex own(R"(by a change to the claim itself \(([^)]*)\))");
  ASSERT_TRUE(std::regex_search(md, m, own));
  EXPECT_NE(m[1].str().find("mechanisms.3"), std::string::npos) << m[1];
  EXPECT_NE(md.find("| mechanisms.3 | statement | the two mechanisms together decimate more than either alone"), std::string::npos);
}

// A pass that holds only at the reading chosen is visible in the summary (#68.4): fig4.2 at Fig. 2's
// 24 rows but not at 8, fig4.3 likewise; and a reading of another quantity (a pulse count beside a
// ratio) is shown as context, never judged against the claim's band. On refsim (seconds): --quick
// runs no 8-row case.
TEST(Reproduce, APassThatHoldsOnlyAtTheChosenReadingIsMarked) {
  const auto md = refsim_report("readings", {"fig4", "eq3"});
  const auto row = [&](const std::string& id) {
    const auto at = md.find("| " + id + " |");
    return at == std::string::npos ? std::string() : md.substr(at, md.find('\n', at) - at);
  };
  EXPECT_NE(row("fig4.2").find("[within at this reading only: outside at pulses.rows8.teflon_over_fig2 = 0.75]"),
            std::string::npos) << row("fig4.2");
  EXPECT_NE(row("fig4.3").find("within at this reading only: outside at "), std::string::npos) << row("fig4.3");
  EXPECT_NE(row("fig4.3").find("sphere.rows8.b2_over_fig2 = 0.57"), std::string::npos) << row("fig4.3");
  EXPECT_EQ(row("eq3.1").find("at this reading only"), std::string::npos);
  EXPECT_NE(md.find("| fig4.2 | pulses.fig2_b2 | 3 | - | context: another quantity, not judged against the band |"),
            std::string::npos);
}

// The numbers in a note, each with how many digits follow its decimal point.
// In a value's name, a number may follow a letter (scan.e0.85.final): `in_name`.
std::vector<std::pair<double, int>> numbers_in(const std::string& text, bool in_name = false) {
  std::vector<std::pair<double, int>> out;
  const std::regex number(in_name ? R"(()([0-9]+\.([0-9]+)))" : R"((^|[^A-Za-z0-9_.])([0-9]+\.([0-9]+)))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it) {
    out.emplace_back(std::stod((*it)[2]), static_cast<int>((*it)[3].length()));
  }
  return out;
}

// Every decimal number the report's prose gives (the analyses' notes) is one of the run's values,
// as a fraction or a percentage, to the digits printed: none is written by hand.
TEST(Reproduce, EveryNumberInTheProseIsOneOfTheRunsValues) {
  const auto j = report();
  int checked = 0;
  for (const auto& e : j.at("experiments")) {
    std::vector<double> values;
    for (const auto& [key, v] : e.at("values").items()) {
      if (v.is_number()) values.push_back(v.get<double>());
      // A parameter a value is named by (the e of scan.e0.85.final) may be quoted too.
      for (const auto& [x, decimals] : numbers_in(key, true)) values.push_back(x);
    }
    for (const auto& note : e.at("notes")) {
      for (const auto& [x, decimals] : numbers_in(note.get<std::string>())) {
        const double unit = std::pow(10.0, -decimals);
        const bool found = std::any_of(values.begin(), values.end(), [&](double v) {
          return std::fabs(v - x) <= 0.5001 * unit || std::fabs(100.0 * v - x) <= 0.5001 * unit;
        });
        EXPECT_TRUE(found) << e.at("name") << ": " << x << " in \"" << note.get<std::string>() << "\"";
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 7);  // fig3's note on the fits
}

TEST(Reproduce, TheNumbersObeyPhysicsComputedHere) {
  const auto j = report();
  // Eq. (3): v_f/v_i = (1 - 2 kappa cos^2 theta) / (1 + 2 kappa cos^2 theta), kappa = 1/8 and
  // cos^2 theta = 8/9 for one material and radius ratio 2: 7/11. A Hertz collision turns the
  // contact normals by ~1e-3 rad while it lasts (measured difference 1.2e-4).
  const auto& eq3 = experiment(j, "eq3").at("values");
  EXPECT_NEAR(eq3.at("v_ratio.steel_rho2").get<double>(), 7.0 / 11.0, 1e-3);
  const double kappa = 2170.0 / 8000.0 / 8.0, k = 2.0 * kappa * 8.0 / 9.0;
  EXPECT_NEAR(eq3.at("v_ratio.steel_on_teflon_rho2").get<double>(), (1 - k) / (1 + k), 1e-3);
  // Fig. 3: the output falls with every block and with every step of damping.
  const auto& fig3 = experiment(j, "fig3").at("values");
  for (const char* e : {"1", "0.99", "0.95", "0.9"}) {
    for (int nb = 1; nb < 4; ++nb) {
      EXPECT_LT(fig3.at(fmt_key(e, nb + 1)).get<double>(), fig3.at(fmt_key(e, nb)).get<double>()) << e << " " << nb;
    }
  }
  for (int nb = 1; nb <= 4; ++nb) EXPECT_LT(fig3.at(fmt_key("0.9", nb)).get<double>(), fig3.at(fmt_key("1", nb)).get<double>());
  // A free-prefactor fit and the one through the origin agree for e = 1 within their errors' reach.
  EXPECT_NEAR(fig3.at("alpha.e1.origin").get<double>(), fig3.at("alpha.e1.free").get<double>(), 0.1);
  // Scale freedom: with e = 1, no friction and no gravity, Hertz dynamics has no length scale,
  // and the automatic dt scales with the radius, so 100 nm spheres give the 1 mm output to
  // round-off (measured 3e-11); a striker 5 times faster, within its larger overlaps' reach.
  const auto& scale = experiment(j, "scale").at("values");
  EXPECT_NEAR(scale.at("output.r100nm_over_r1mm").get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(scale.at("output.r10um_over_r1mm").get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(scale.at("output.v5_over_v1").get<double>(), 1.0, 0.01);
  // Fig. 2's per-sphere readings: the pulse splits at every interface, so the middle-row sphere's
  // peak falls block by block, and the leading wave moves at Nesterenko's speed.
  const auto& fig2 = experiment(j, "fig2").at("values");
  EXPECT_LT(fig2.at("sphere.free.b2").get<double>(), 1.0);
  EXPECT_LT(fig2.at("sphere.free.b3").get<double>(), fig2.at("sphere.free.b2").get<double>());
  EXPECT_LT(fig2.at("sphere.free.b4").get<double>(), fig2.at("sphere.free.b3").get<double>());
  EXPECT_NEAR(fig2.at("speed_ratio.worst").get<double>(), 1.0, 0.1);
  // Fig. 4: Nesterenko's speed scales as (Y / (D rho^(3/2) (1 - nu^2)))^(1/3) F^(1/6); in Teflon
  // the wave is several times slower than in steel of the same size.
  const auto& fig4 = experiment(j, "fig4").at("values");
  EXPECT_LT(fig4.at("speed.teflon_over_steel").get<double>(), 0.5);
}

// Beyond the paper (#67 item 6): Fig. 3's stacks under Thornton's law, which only refsim has, run
// there while the reproduction runs on LIGGGHTS, which runs one block under its thornton_ning. The
// physics: each series decays with depth; yield takes a share of E_in that with the output stays
// within E_in and grows with the speed; the annealed steel passes on less than the hardened grade at
// every speed; at 0.1 m/s the hardened grade stays below first yield, dissipates nothing and gives
// the elastic outputs (measured: 1.3e-3 apart at most); there one block under thornton_ning gives
// Thornton's output to 1 % (measured 0.6 %: thornton_ning's step, t_c / 1000, first order in dt).
// The sandwich and the friction study's stack run the same way. No claim of the paper's is judged,
// and the section stands apart from the summary.
TEST(Reproduce, TheStudyUnderPlasticityRunsThorntonOnRefsimBesideTheReproductionsEngine) {
  const auto d = work() / "plasticity";
  fs::remove_all(d);
  const auto r = granstack({"reproduce", "-j", "2", "-o", d.string(), "plasticity"});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rep = nlohmann::json::parse(read_bytes(d / "report.json"));
  EXPECT_EQ(rep.at("engine"), "liggghts");
  const auto& e = experiment(rep, "plasticity");
  EXPECT_TRUE(e.at("beyond").get<bool>());
  EXPECT_TRUE(e.at("claims").empty());
  for (const auto& c : e.at("cases")) {
    const auto name = c.at("name").get<std::string>();
    EXPECT_EQ(c.at("status"), "done") << name;
    EXPECT_EQ(c.at("engine"), name.rfind("ning", 0) == 0 ? "liggghts" : "refsim") << name;
  }
  const auto& v = e.at("values");
  const auto value = [&](const std::string& key) { return v.at(key).get<double>(); };
  for (const std::string grade : {"steel", "steel_4340"}) {
    double previous_yield = -1.0;
    for (const char* speed : {"0.1", "1", "2"}) {
      const auto key = grade + ".v" + speed;
      for (int nb = 2; nb <= 4; ++nb) {
        EXPECT_LT(value(fmt_key_of(key, nb)), value(fmt_key_of(key, nb - 1))) << key << " nb" << nb;
      }
      const double yield = value("dissipated." + key);
      EXPECT_GE(yield, 0.0) << key;
      EXPECT_LE(yield + value(fmt_key_of(key, 4)), 1.0) << key;
      EXPECT_GE(yield, previous_yield) << key << ": yield takes more at a higher speed";
      previous_yield = yield;
      if (grade == "steel") {
        EXPECT_LT(value(fmt_key_of(key, 4)), value(fmt_key_of("steel_4340.v" + std::string(speed), 4))) << key;
      }
    }
  }
  EXPECT_EQ(value("dissipated.steel_4340.v0.1"), 0.0);
  for (int nb = 1; nb <= 4; ++nb) {
    const double hard = value(fmt_key_of("steel_4340.v0.1", nb)), elastic = value(fmt_key_of("elastic", nb));
    EXPECT_NEAR(hard / elastic, 1.0, 1e-2) << nb;
  }
  EXPECT_NEAR(value("ning_over_thornton.steel_4340.v0.1"), 0.0, 1e-2);
  // The sandwich: elastic, less than three steel blocks (the paper's claim); yielding, every
  // block's dissipated work is read where the blow ended, and with the output stays within E_in.
  EXPECT_LT(value("sandwich_over_steel3.elastic"), 1.0);
  for (const std::string grade : {"steel", "steel_4340"}) {
    for (const char* speed : {"0.1", "1", "2"}) {
      const auto key = grade + ".v" + speed;
      double yield = 0.0;
      for (int b = 1; b <= 3; ++b) yield += value("dissipated.sandwich." + key + ".b" + std::to_string(b));
      EXPECT_LE(yield + value("sandwich." + key), 1.0) << key;
    }
  }
  for (const char* series : {"friction_elastic", "friction", "friction_4340"}) {
    for (const char* mu : {"0", "0.1", "0.25"}) EXPECT_GT(value(std::string("output.") + series + ".mu" + mu), 0.0) << series << mu;
  }
  // The decay figure draws the table's outputs: the elastic series' four points, to the digits written.
  const auto dat = read_bytes(d / "figures" / "plasticity_decay.dat");
  EXPECT_TRUE(fs::is_regular_file(d / "figures" / "plasticity_decay.svg"));
  const auto elastic_at = dat.find("# elastic (Hertz, e = 1), any speed");
  ASSERT_NE(elastic_at, std::string::npos) << dat;
  std::istringstream elastic_points(dat.substr(dat.find('\n', elastic_at) + 1));
  for (int nb = 1; nb <= 4; ++nb) {
    int n = 0;
    double f = 0.0;
    ASSERT_TRUE(elastic_points >> n >> f);
    EXPECT_EQ(n, nb);
    EXPECT_NEAR(f / value(fmt_key_of("elastic", nb)), 1.0, 1e-9) << nb;
  }
  // On LAMMPS, which has no elastic-plastic law: the thornton_ning check is not run and says why,
  // nothing fails, and the pinned cases run on refsim by its own rules, to the same bits.
  const auto l = work() / "plasticity_lammps";
  fs::remove_all(l);
  const auto on_lammps = granstack({"reproduce", "-j", "2", "--engine", "lammps", "-o", l.string(), "plasticity"});
  ASSERT_EQ(on_lammps.code, 0) << on_lammps.output;
  const auto lrep = nlohmann::json::parse(read_bytes(l / "report.json"));
  const auto& le = experiment(lrep, "plasticity");
  for (const auto& c : le.at("cases")) {
    const auto name = c.at("name").get<std::string>();
    if (name.rfind("ning", 0) == 0) {
      EXPECT_EQ(c.at("status"), "not run") << name;
      EXPECT_NE(c.at("problem").get<std::string>().find("not run on lammps: normal_model = 'thornton_ning'"), std::string::npos) << name;
    } else {
      EXPECT_EQ(c.at("engine"), "refsim") << name;
    }
  }
  for (const char* key : {"output.steel.v1.nb4", "dissipated.steel_4340.v2", "sandwich.steel.v1", "output.friction.mu0.25"}) {
    EXPECT_EQ(le.at("values").at(key).get<double>(), value(key)) << key;
  }
  const auto md = read_bytes(d / "report.md");
  EXPECT_LT(md.find("## Beyond the paper"), md.find("### plasticity: Decimation when the contacts yield"));
  EXPECT_NE(md.find("Under yield each block still passes on a share of what reaches it"), std::string::npos);
}

TEST(Reproduce, ARerunReusesEveryFinishedCaseAndRunsOnlyWhatIsMissing) {
  const auto dir = quick_dir();
  const auto case_dir = dir / "eq3" / "steel_rho2";
  const auto before = fs::last_write_time(dir / "fig3" / "nb4_e1" / "run.json");
  fs::remove_all(case_dir);  // as if the reproduction had been stopped before this case
  const auto r = granstack({"reproduce", "--quick", "-o", dir.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  // Exactly one case ran: the one that was missing.
  const std::regex done_line("(^|\n)done ");
  EXPECT_EQ(std::distance(std::sregex_iterator(r.output.begin(), r.output.end(), done_line), std::sregex_iterator()), 1) << r.output;
  EXPECT_NE(r.output.find("done     " + case_dir.string()), std::string::npos) << r.output;
  EXPECT_EQ(fs::last_write_time(dir / "fig3" / "nb4_e1" / "run.json"), before);
}

// Ctrl-C in the middle: granstack stops (130), its finished cases stay done; the same command
// again runs exactly the cases that were not done and writes the whole report.
TEST(Reproduce, AStoppedReproductionContinuesWhereItStopped) {
  const auto dir = test::scratch(work() / "stopped");
  fs::remove_all(dir);
  const auto log = work() / "stopped_first_run.txt";
  os::StartOptions o;
  o.output = log;
  const auto child = os::start({GRANSTACK_EXE, "reproduce", "fig3", "eq3", "-o", dir.string()}, o);
  ASSERT_GT(child.pid, 0) << child.error;
  auto done_cases = [&] {
    std::map<fs::path, fs::file_time_type> done;
    // granstack renames folders into place meanwhile: an entry that vanishes is skipped.
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      const auto& e = *it;
      if (e.path().filename() == "run.json" && read_bytes(e.path()).find("\"status\": \"done\"") != std::string::npos) {
        std::error_code time_ec;
        const auto time = fs::last_write_time(e.path(), time_ec);
        if (!time_ec) done[e.path()] = time;
      }
    }
    return done;
  };
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (done_cases().size() < 3 && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(child.pid, SIGINT);
  const auto end = os::wait(child);
  EXPECT_EQ(end.code, 130) << read_bytes(log);
  const auto before = done_cases();
  ASSERT_GE(before.size(), 3u);
  ASSERT_LT(before.size(), 25u) << "the reproduction finished before it could be stopped";
  const auto r = granstack({"reproduce", "fig3", "eq3", "-o", dir.string(), "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.output;
  const std::regex done_line("(^|\n)done ");
  EXPECT_EQ(std::distance(std::sregex_iterator(r.output.begin(), r.output.end(), done_line), std::sregex_iterator()),
            static_cast<long>(25 - before.size()))
      << r.output;
  for (const auto& [path, time] : before) EXPECT_EQ(fs::last_write_time(path), time) << path << " ran again";
  EXPECT_EQ(done_cases().size(), 25u);  // fig3's 4 x 4 sweep and two heights, fig2's 3 stacks (fig3.8 reads one), eq3's 4
  const auto j = nlohmann::json::parse(read_bytes(dir / "report.json"));
  EXPECT_EQ(j.at("failed_cases"), 0);
  for (const auto& e : j.at("experiments")) {
    for (const auto& c : e.at("claims")) EXPECT_EQ(c.at("verdict"), c.at("expect")) << c.at("id");
  }
}

TEST(Reproduce, AnUnknownExperimentAndADirectoryOfTheUsersAreRefused) {
  auto r = granstack({"reproduce", "fig9", "-o", (work() / "never").string()});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown experiment 'fig9'; known: fig2, fig3, scale, friction, fig4, sandwich, container, eq3, eq45, mechanisms, rows"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(work() / "never"));
  const auto mine = test::scratch(work() / "mine");
  fs::remove_all(mine);
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "precious";
  r = granstack({"reproduce", "eq3", "-o", mine.string()});
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("was not made by granstack"), std::string::npos) << r.output;
  EXPECT_EQ(read_bytes(mine / "thesis.tex"), "precious");
  EXPECT_EQ(std::distance(fs::directory_iterator(mine), fs::directory_iterator()), 1);
}

// Part of the study on LAMMPS set beside the LIGGGHTS one (reproduce --engine lammps --against):
// every verdict stays, each claim's difference is named (round-off, or the damping or friction
// model where the spec has them), and a reproduction of the same engine is refused before
// anything is made.
TEST(Reproduce, TheStudyOnLammpsKeepsEveryVerdictAndNamesEachDifference) {
  const auto dir = test::scratch(work() / "lammps");
  fs::remove_all(dir);
  // The quick cases of Fig. 3 (its damped restitution scan) and the scale experiment (and what
  // they need), against the quick study.
  auto r = granstack({"reproduce", "--quick", "fig3", "scale", "-j", "2", "--engine", "lammps", "--against",
                      quick_dir().string(), "-o", dir.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("against liggghts (" + quick_dir().string() + "): 0 of "), std::string::npos) << r.output;
  const auto j = nlohmann::json::parse(read_bytes(dir / "report.json"));
  EXPECT_EQ(j.at("engine"), "lammps");
  const auto& against = j.at("against");
  EXPECT_EQ(against.at("engine"), "liggghts");
  EXPECT_EQ(against.at("changed"), 0);
  std::size_t claims = 0;
  for (const auto& e : j.at("experiments")) claims += e.at("claims").size();
  ASSERT_GT(claims, 10u);
  ASSERT_EQ(against.at("claims").size(), claims);
  for (const auto& c : against.at("claims")) {
    EXPECT_NE(c.at("verdict_there"), "not run") << c.at("claim");  // every claim is in the LIGGGHTS report
    EXPECT_EQ(c.at("verdict_here"), c.at("verdict_there")) << c.at("claim");
    const auto cause = c.at("cause").get<std::string>();
    if (!c.at("relative").is_number()) {
      EXPECT_EQ(cause, "not measured on either engine") << c.at("claim");
      EXPECT_EQ(c.at("verdict_here"), "not measured") << c.at("claim");
    } else if (c.at("relative").get<double>() <= 1e-12) {
      EXPECT_EQ(cause.rfind("none beyond round-off", 0), 0u) << c.at("claim") << ": " << cause;
    } else {
      EXPECT_TRUE(cause.find("damping:") != std::string::npos || cause.find("friction:") != std::string::npos)
          << c.at("claim") << ": " << cause;
    }
  }
  EXPECT_NE(read_bytes(dir / "report.md").find("## Against liggghts"), std::string::npos);
  const auto never = work() / "lammps_again";
  fs::remove_all(never);
  r = granstack({"reproduce", "--quick", "scale", "--engine", "lammps", "--against", dir.string(), "-o", never.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("that reproduction ran on lammps too"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(never));
  // Its report vouched for by its digest, as its cases are by theirs (#65 M6): a value edited by
  // hand, its verdict with it, is refused by name before anything is made.
  auto edited = nlohmann::json::parse(read_bytes(dir / "report.json"));
  auto& claim = edited.at("experiments").at(0).at("claims").at(0);
  claim["value"] = 123.0;
  claim["verdict"] = "within";
  std::ofstream(dir / "report.json") << edited.dump(2) << "\n";
  r = granstack({"reproduce", "--quick", "scale", "--engine", "refsim", "--against", dir.string(), "-o", never.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("report.json was edited after `granstack reproduce` wrote it"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(never));
}

// The rows of a gnuplot data file: (its index, counting blocks parted by two blank lines; its fields).
std::vector<std::pair<int, std::vector<std::string>>> gnuplot_rows(const std::string& text) {
  std::vector<std::pair<int, std::vector<std::string>>> out;
  std::istringstream lines(text);
  std::string line;
  int index = 0, blank = 0;
  bool any = false;
  while (std::getline(lines, line)) {
    if (line.empty()) {
      ++blank;
      continue;
    }
    if (blank >= 2 && any) ++index;
    blank = 0;
    if (line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string f; fields >> f;) row.push_back(f);
    out.emplace_back(index, std::move(row));
    any = true;
  }
  return out;
}

// The figures the referee found wanting (fourth round, item 6), on refsim (the figures are the same
// on every engine): each e of the decay its own marker; the stack drawn beside its lowest blocks
// magnified, the output sphere among them; whole blocks with no inset when they are as large as the
// scale, the time axis ending where the blocks have settled; the output figure's key outside its
// curves and no read-out line past the data; the friction bars filling the plot's width.
TEST(Reproduce, TheFiguresShowWhatTheirCaptionsSay) {
  const auto dir = test::scratch(work() / "figures");
  fs::remove_all(dir);
  const auto r = granstack({"reproduce", "fig2", "fig3", "fig4", "friction", "--engine", "refsim", "-j", "2", "-o", dir.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto figures = dir / "figures";
  const auto gp = [&](const std::string& name) { return read_bytes(figures / (name + ".gp")); };
  const auto all = [](const std::string& text, const std::string& pattern) {
    std::vector<std::smatch> out;
    const std::regex re(pattern);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) out.push_back(*it);
    return out;
  };
  // Decay: one marker per e.
  const auto decay = gp("decay");
  std::map<std::string, std::string> marker;  // pointtype -> e
  for (const auto& m : all(decay, R"(pointtype (\d+)[^\n]* title 'e = ([0-9.]+)')")) {
    EXPECT_TRUE(marker.emplace(m[1].str(), m[2].str()).second) << "e = " << m[2] << " and e = " << marker[m[1].str()] << " share a marker";
  }
  EXPECT_GE(marker.size(), 4u);
  // The stack drawing: a second panel, the lowest blocks, holding the output sphere (colour 6).
  const auto stack = gp("fig1a_stack");
  EXPECT_NE(stack.find("index 1 using"), std::string::npos) << stack;
  std::set<int> output_sphere_in;  // the data blocks (gnuplot's indices) holding colour 6
  for (const auto& [index, fields] : gnuplot_rows(read_bytes(figures / "fig1a_stack.dat"))) {
    if (fields.size() == 4 && fields[3] == "6") output_sphere_in.insert(index);
  }
  EXPECT_EQ(output_sphere_in, (std::set<int>{0, 1}));  // the whole stack and the magnified blocks
  // Whole blocks: blocks 3 and 4 reach 0.4 and 0.65 of block 1's peak, no inset; the axis ends
  // where they have settled, well before the run's end.
  const auto blocks = gp("fig2_blocks");
  EXPECT_EQ(blocks.find("inset"), std::string::npos);
  std::smatch range;
  ASSERT_TRUE(std::regex_search(blocks, range, std::regex(R"(set xrange \[([0-9.e+-]+):([0-9.e+-]+)\])")));
  double last = 0.0;
  for (const auto& [index, fields] : gnuplot_rows(read_bytes(figures / "fig2_blocks.dat"))) last = std::max(last, std::stod(fields[0]));
  EXPECT_LT(std::stod(range[2]), 0.7 * last);  // measured 0.55
  // The output figure: its key below the plot; a read-out line only where a curve reaches it.
  const auto output = gp("steel_on_teflon_output");
  EXPECT_NE(output.find("set key below"), std::string::npos);
  EXPECT_EQ(output.find("opaque"), std::string::npos);
  double data_end = 0.0;
  for (const auto& [index, fields] : gnuplot_rows(read_bytes(figures / "steel_on_teflon_output.dat"))) {
    data_end = std::max(data_end, std::stod(fields[0]));
  }
  std::smatch arrow;
  if (std::regex_search(output, arrow, std::regex(R"(set arrow 100 from ([0-9.e+-]+),)"))) {
    EXPECT_LE(std::stod(arrow[1]), data_end);
  } else {
    EXPECT_NE(output.find("come after every run had stopped"), std::string::npos) << output;
  }
  // The friction bars: 6 groups at 0 to 5, the axis no wider than a group's half-width past them.
  const auto friction = gp("friction_sideways");
  std::smatch bars;
  ASSERT_TRUE(std::regex_search(friction, bars, std::regex(R"(set xrange \[([0-9.e+-]+):([0-9.e+-]+)\])")));
  EXPECT_LE(std::stod(bars[2]), 5.6);
}

// The HTML report in a real browser (Debian's Chromium, headless, no network): it loads, every
// figure is an inline SVG the browser parsed into drawn paths, and nothing is fetched from elsewhere.
TEST(Reproduce, TheHtmlReportIsSelfContainedAndItsFiguresRenderInChromium) {
  const auto chromium = os::find_program("chromium");
  if (!chromium) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh --tests installs it)";
  const auto html = quick_dir() / "report.html";
  const auto text = read_bytes(html);
  for (const char* fetch : {"<script", "<link", " src=", "url(", "@import"}) {
    EXPECT_EQ(text.find(fetch), std::string::npos) << "the report loads something: " << fetch;
  }
  const auto r = run({*chromium, "--headless", "--no-sandbox", "--disable-gpu", "--host-resolver-rules=MAP * ~NOTFOUND",
                      "--dump-dom", "file://" + fs::absolute(html).string()});
  ASSERT_EQ(r.code, 0) << r.output.substr(0, 2000);
  const auto j = report();
  std::size_t figures = 0;
  for (const auto& e : j.at("experiments")) figures += e.at("figures").size();
  ASSERT_GE(figures, 4u);
  // The DOM Chromium built: one <svg> per figure, each with drawn paths and its caption.
  std::size_t svgs = 0, pos = 0;
  while ((pos = r.output.find("<svg", pos)) != std::string::npos) {
    const auto end = r.output.find("</svg>", pos);
    ASSERT_NE(end, std::string::npos);
    EXPECT_NE(r.output.substr(pos, end - pos).find("<path"), std::string::npos) << "figure " << svgs + 1 << " draws nothing";
    ++svgs;
    pos = end;
  }
  EXPECT_EQ(svgs, figures);
  EXPECT_NE(r.output.find("<figcaption>Fig. 3 re-made"), std::string::npos);
  EXPECT_NE(r.output.find("<td class=\"outside\">outside, by"), std::string::npos);  // the verdicts are marked
}

}  // namespace
