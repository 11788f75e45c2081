// `granstack export` on a case run with the real LIGGGHTS, read back with VTK's own XML reader
// (Debian's python3-vtk9, tests/support/read_vtk.py): every sphere's position and velocity the
// dump's to the bit, each sphere's kinetic energy its 1/2 m v^2 + 1/5 m r^2 w^2, their sum
// LIGGGHTS's own in-situ energy, times step x dt; and the refusals.
#include "../support/program.hpp"
#include "../support/scratch.hpp"

#include <granstack/formats/dump.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using namespace granstack;

namespace {

const fs::path& work() {
  static const fs::path dir = test::scratch_for_process(fs::path(GRANSTACK_TEST_WORKDIR) / "export");
  return dir;
}

test::ProgramResult run(std::vector<std::string> argv) { return test::run_program(std::move(argv), work() / "last_output.txt"); }

test::ProgramResult granstack(std::vector<std::string> args) {
  args.insert(args.begin(), GRANSTACK_EXE);
  return run(args);
}

// A small stack (3 blocks of 4 rows under 2 top columns: 56 spheres and the striker), run once
// on LIGGGHTS with e = 0.9 and friction, so that spheres spin.
const fs::path& case_dir() {
  static const fs::path dir = [] {
    const auto d = work() / "stack";
    fs::remove_all(work());
    fs::create_directories(work());
    auto r = granstack({"generate", "-o", d.string(), "--blocks", "3", "--rows", "4", "--restitution", "0.9", "--friction", "0.25"});
    EXPECT_EQ(r.code, 0) << r.output;
    r = granstack({"run", d.string()});
    EXPECT_EQ(r.code, 0) << r.output;
    return d;
  }();
  return dir;
}

// What VTK read from a .pvd, or skipped when VTK's Python bindings are missing.
nlohmann::json read_with_vtk(const fs::path& pvd) {
  const auto r = run({"/usr/bin/python3", fs::path(GRANSTACK_SOURCE_DIR) / "tests/support/read_vtk.py", pvd.string()});
  if (r.code == 77) return nlohmann::json{{"skip", r.output}};
  EXPECT_EQ(r.code, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

// The dump's frames by step.
std::map<long, formats::DumpFrame> dump_frames(const fs::path& dir) {
  const auto m = formats::read_manifest(dir.string());
  const auto reader = formats::open_dump(formats::find_dump(dir.string(), m.files.dump), false, m.files.dump_columns);
  std::map<long, formats::DumpFrame> frames;
  formats::DumpFrame f;
  while (reader->next(f)) frames[f.step] = f;
  return frames;
}

TEST(Export, VtkReadsEverySphereOfTheChosenFramesAsTheDumpHasIt) {
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3: VTK's reader cannot run";
  const auto r = granstack({"export", case_dir().string(), "--frames", "0,::7,-1"});
  ASSERT_EQ(r.code, 0) << r.output;
  const fs::path pvd = case_dir() / "paraview" / "stack.pvd";
  EXPECT_NE(r.output.find(pvd.string()), std::string::npos) << r.output;
  const auto vtk = read_with_vtk(pvd);
  if (vtk.contains("skip")) GTEST_SKIP() << vtk.at("skip").get<std::string>();

  const auto m = formats::read_manifest(case_dir().string());
  const auto stack = model::Stack::build(m.spec);
  const long every = m.derived->at("dump_every"), steps = m.derived->at("steps");
  const double dt = m.derived->at("dt");
  const auto frames = dump_frames(case_dir());
  const auto series = formats::read_series((case_dir() / m.files.series).string());
  const long count = steps / every + 1;
  std::vector<long> expected;
  for (long k = 0; k < count; ++k) {
    if (k == 0 || k % 7 == 0 || k == count - 1) expected.push_back(k * every);
  }
  const auto& got = vtk.at("frames");
  ASSERT_EQ(got.size(), expected.size());
  const std::size_t n = stack.spheres().size();
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const auto& g = got[k];
    const long step = expected[k];
    EXPECT_EQ(g.at("time").get<double>(), static_cast<double>(step) * dt) << step;
    ASSERT_EQ(g.at("points").get<std::size_t>(), n);
    EXPECT_EQ(g.at("verts").get<std::size_t>(), n);
    const auto& f = frames.at(step);
    const auto& a = g.at("arrays");
    std::map<long, int> per_block;
    double total = 0.0;
    for (long row = 0; row < f.atoms; ++row) {
      const auto id = static_cast<std::size_t>(f.at(row, f.column("id")));
      const std::size_t i = id - 1;  // VTK's points are in id order
      ASSERT_EQ(a.at("id")[i].get<double>(), static_cast<double>(id));
      for (int d = 0; d < 3; ++d) {
        const char* xs[] = {"x", "y", "z"};
        const char* vs[] = {"vx", "vy", "vz"};
        EXPECT_EQ(g.at("xyz")[3 * i + static_cast<std::size_t>(d)].get<double>(), f.at(row, f.column(xs[d]))) << id;
        EXPECT_EQ(a.at("velocity")[3 * i + static_cast<std::size_t>(d)].get<double>(), f.at(row, f.column(vs[d]))) << id;
      }
      const double mass = f.at(row, f.column("mass")), rad = f.at(row, f.column("radius"));
      const double vx = f.at(row, f.column("vx")), vy = f.at(row, f.column("vy")), vz = f.at(row, f.column("vz"));
      const double wx = f.at(row, f.column("omegax")), wy = f.at(row, f.column("omegay")), wz = f.at(row, f.column("omegaz"));
      const double expected_ke = 0.5 * mass * (vx * vx + vy * vy + vz * vz) + 0.2 * mass * rad * rad * (wx * wx + wy * wy + wz * wz);
      const double ke = a.at("kinetic_energy")[i];
      EXPECT_NEAR(ke, expected_ke, 1e-15 * expected_ke + 1e-300) << id;
      total += ke;
      ++per_block[static_cast<long>(a.at("block")[i].get<double>())];
    }
    // The spheres' energies add up to LIGGGHTS's own in-situ sums (blocks and striker), and at
    // step 0 (before the series' first row) to the striker's 1/2 m v0^2.
    double engine = m.derived->at("e_in");
    const auto at_step = std::find_if(series.rows.begin(), series.rows.end(),
                                      [&](const auto& row) { return row.at(0) == static_cast<double>(step); });
    if (step != 0) {
      ASSERT_NE(at_step, series.rows.end()) << "no series row at step " << step;
      const auto& row = *at_step;
      const auto value = [&](const std::string& column) { return row.at(static_cast<std::size_t>(series.column(column))); };
      engine = value("ke_trans_striker") + value("ke_rot_striker");
      for (int b = 1; b <= m.spec.blocks; ++b) engine += value(fmt::format("ke_trans_block{}", b)) + value(fmt::format("ke_rot_block{}", b));
    }
    EXPECT_NEAR(total, engine, 1e-12 * engine) << "step " << step;
    // Block 0 is the striker; block k holds top_columns 2^(k-1) columns of `rows` spheres.
    EXPECT_EQ(per_block[0], 1);
    for (int b = 1; b <= m.spec.blocks; ++b) EXPECT_EQ(per_block[b], m.spec.rows * m.spec.top_columns * (1 << (b - 1))) << b;
  }
  // The impact got under way in the frames written: the striker's energy went into the stack.
  const auto& last = got.back().at("arrays").at("kinetic_energy");
  EXPECT_LT(last[0].get<double>(), 0.5 * got.front().at("arrays").at("kinetic_energy")[0].get<double>());
}

TEST(Export, RefusesWhatItMustNotDoAndLosesNothing) {
  const auto dir = case_dir().string();
  // A bad selection: exit 2, the fix named, nothing written.
  auto r = granstack({"export", dir, "-o", (work() / "bad").string(), "--frames", "1:x"});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("'x' is not a whole number"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(work() / "bad"));
  r = granstack({"export", dir, "-o", (work() / "bad").string(), "--frames", "100000"});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("is not one of the dump's"), std::string::npos) << r.output;

  // An earlier export is not replaced without --force; with it, it is.
  const auto out = work() / "again";
  ASSERT_EQ(granstack({"export", dir, "-o", out.string(), "--frames", "0"}).code, 0);
  r = granstack({"export", dir, "-o", out.string(), "--frames", "0"});
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_EQ(granstack({"export", dir, "-o", out.string(), "--frames", "0", "--force"}).code, 0);

  // A user's directory holding a file of the same name is never written into, even with --force.
  const auto mine = work() / "mine";
  fs::create_directories(mine);
  std::ofstream(mine / "stack.pvd") << "my notes\n";
  r = granstack({"export", dir, "-o", mine.string(), "--frames", "0", "--force"});
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_EQ(test::read_bytes(mine / "stack.pvd"), "my notes\n");

  // A case that has not run: exit 1, saying so (as reduce does), and how to run it.
  const auto unrun = work() / "unrun";
  ASSERT_EQ(granstack({"generate", "-o", unrun.string(), "--blocks", "1", "--rows", "2"}).code, 0);
  r = granstack({"export", unrun.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("the case has not been run; run 'granstack run"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(unrun / "paraview" / "unrun.pvd"));
}

}  // namespace

namespace {

// A 3D nest exports its y positions and y-columns too.
TEST(Export, ANestExportsItsThirdDimension) {
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3: VTK's reader cannot run";
  const auto dir = work() / "nest";
  ASSERT_EQ(granstack({"generate", "-o", dir.string(), "--geometry", "nested3d", "--blocks", "2", "--rows", "2", "--force"}).code, 0);
  ASSERT_EQ(granstack({"run", "--force", dir.string()}).code, 0);
  ASSERT_EQ(granstack({"export", dir.string(), "--frames", "-1", "--force"}).code, 0);
  const auto vtk = read_with_vtk(dir / "paraview" / "nest.pvd");
  if (vtk.contains("skip")) GTEST_SKIP() << vtk.at("skip").get<std::string>();
  const auto stack = model::Stack::build(formats::read_manifest(dir.string()).spec);
  const auto& frame = vtk.at("frames").at(0);
  ASSERT_EQ(frame.at("points").get<std::size_t>(), stack.spheres().size());
  const auto last = dump_frames(dir).rbegin()->second;
  for (long row = 0; row < last.atoms; ++row) {
    const auto id = static_cast<std::size_t>(last.at(row, last.column("id")));
    EXPECT_EQ(frame.at("xyz")[3 * (id - 1) + 1].get<double>(), last.at(row, last.column("y"))) << id;
    EXPECT_EQ(frame.at("arrays").at("column_y")[id - 1].get<double>(), stack.sphere(static_cast<int>(id)).column_y) << id;
  }
}

}  // namespace

namespace {

// A container exports each sphere's panel and matrix chain: the per-sphere kinetic energies VTK
// reads, summed by panel and over the matrix, are reduce's panel_ke.csv at the last frame (to
// round-off: two sums of the same numbers in another order); and `plot` draws the panels.
TEST(Export, AContainerExportsItsPanelsAndMatrixAndPlotsThem) {
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3: VTK's reader cannot run";
  const auto dir = work() / "container";
  ASSERT_EQ(granstack({"generate", "-o", dir.string(), "--geometry", "panels", "--panels", "3", "--blocks", "2", "--rows",
                       "3", "--impact-panel", "1", "--force"})
                .code,
            0);
  ASSERT_EQ(granstack({"run", "--force", dir.string()}).code, 0);
  ASSERT_EQ(granstack({"reduce", dir.string()}).code, 0);
  ASSERT_EQ(granstack({"export", dir.string(), "--frames", "-1", "--force"}).code, 0);
  const auto vtk = read_with_vtk(dir / "paraview" / "container.pvd");
  if (vtk.contains("skip")) GTEST_SKIP() << vtk.at("skip").get<std::string>();
  const auto stack = model::Stack::build(formats::read_manifest(dir.string()).spec);
  const auto& arrays = vtk.at("frames").at(0).at("arrays");
  std::vector<double> panels(4, 0.0);  // index 0: the matrix
  double striker = 0.0;
  for (const auto& s : stack.spheres()) {
    const auto i = static_cast<std::size_t>(s.id - 1);
    const auto panel = static_cast<std::size_t>(arrays.at("panel")[i].get<double>());
    const bool matrix = arrays.at("matrix_chain")[i].get<double>() > 0;
    EXPECT_EQ(matrix, stack.is_matrix(s)) << s.id;
    ASSERT_LE(panel, 3U);
    EXPECT_EQ(panel == 0, matrix || s.block == 0) << s.id;
    (s.block == 0 ? striker : panels[panel]) += arrays.at("kinetic_energy")[i].get<double>();
  }
  std::ifstream csv(dir / "reduce" / "panel_ke.csv");
  std::string header, line, last;
  std::getline(csv, header);
  while (std::getline(csv, line)) last = line;
  EXPECT_EQ(header.substr(0, 62), "step,time_s,ke_panel1_J,ke_panel2_J,ke_panel3_J,ke_matrix_J,ke");
  std::vector<double> values;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) values.push_back(std::stod(cell));
  const double e_in = stack.incident_energy();
  for (std::size_t p = 1; p <= 3; ++p) EXPECT_NEAR(panels[p], values[1 + p], 1e-13 * e_in) << "panel " << p;
  EXPECT_NEAR(panels[0], values[5], 1e-13 * e_in) << "matrix";
  EXPECT_GT(panels[1], panels[3]);  // the striker hit panel 1
  EXPECT_GT(panels[0], 0.0);

  const auto figures = work() / "container_plots";
  ASSERT_EQ(granstack({"plot", dir.string(), "-o", figures.string(), "--force"}).code, 0);
  std::ifstream png(figures / "panels_container.png", std::ios::binary);
  std::string magic(8, '\0');
  png.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");
  std::ifstream data(figures / "panels_container.dat");
  std::getline(data, line);
  std::getline(data, line);
  EXPECT_EQ(std::count(line.begin(), line.end(), ' '), 4) << line;  // time, 3 panels, the matrix
}

}  // namespace
