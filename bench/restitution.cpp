// The restitution of refsim's two elastic-plastic laws against Thornton (1997)'s closed form: a
// sphere of radius 2 mm striking a wall of its own material head on, p_y = 1.6 Y, each law at
// granstack's automatic time step (thornton t_c / 100, thornton_ning t_c / 1000, t_c Hertz's
// contact time at the speed), for the materials table's yielding materials, annealed and
// hardened, at 0.5, 1 and 2 m/s;
// and thornton_ning's first-order error in dt (an impact that never yields, e - 1 at t_c / 100 and
// t_c / 1000). refsim runs thornton_ning by LIGGGHTS's rules, bit for bit with LIGGGHTS 3.8
// (tests/data/twobody). Writes the record as JSON on stdout: bench/results/restitution-DATE.json,
// from which scripts/doc_tables.py makes docs/physics.md's table.
// Usage: granstack_bench_restitution > bench/results/restitution-DATE.json
#include <granstack/model/contact.hpp>
#include <granstack/model/material.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/format.h>

#include <string>
#include <vector>

namespace {
using namespace granstack;

constexpr double kRadius = 2e-3;
constexpr double kFactor = 1.6;  // p_y / Y: first yield

// The sphere's rebound speed over its impact speed `v` under the law of `p`, at time step dt.
double rebound(const model::Material& m, refsim::Parameters p, double v) {
  p.walls.push_back({2, 0.0, 2});
  refsim::System s({{1, kRadius, model::sphere_mass(kRadius, m.density), {0, 0, kRadius * 1.0001}, {0, 0, -v}, {0, 0, 0}}},
                   p);
  s.setup();
  bool touched = false;
  for (long k = 0; k < 10'000'000; ++k) {
    s.step();
    const double overlap = kRadius - s.x(0)[2];
    touched = touched || overlap > 0.0;
    if (touched && overlap <= 0.0) break;
  }
  return s.v(0)[2] / v;
}

refsim::Parameters law(const model::Material& m, model::NormalModel normal, double dt) {
  auto p = refsim::uniform_parameters({m, m}, 1.0, 0.0, dt, 1e-4);
  p.contact.normal = normal;
  const double p_y = kFactor * *m.yield_strength;
  p.yield_pressure.assign(4, p_y);
  // thornton_ning's a_y = r * ratio: pi R* p_y / (2 E*), R* = r on a wall.
  const double ratio = model::kPi * p_y / (2.0 * model::sphere_wall(m, kRadius, m).y_star);
  p.yield_ratio = {ratio, ratio};
  return p;
}
}  // namespace

int main() {
  const auto library = model::MaterialLibrary::builtin();
  std::vector<std::string> rows;
  for (const char* name : {"steel", "aluminium", "brass", "nylon", "teflon", "steel_4340", "aluminium_7075", "brass_h04"}) {
    const auto& m = library.at(name);
    const auto c = model::sphere_wall(m, kRadius, m);
    const double v_y = model::thornton_yield_velocity(c, kFactor * *m.yield_strength);
    for (const double v : {0.5, 1.0, 2.0}) {
      const double t_c = model::hertz_contact_time(c, v);
      rows.push_back(fmt::format(
          R"(    {{"material": "{}", "speed": {}, "yield_velocity": {:.6g}, "closed_form": {:.6f}, "thornton": {:.6f}, )"
          R"("thornton_ning": {:.6f}}})",
          name, v, v_y, model::thornton_restitution(v_y, v), rebound(m, law(m, model::NormalModel::thornton, t_c / 100), v),
          rebound(m, law(m, model::NormalModel::thornton_ning, t_c / 1000), v)));
    }
  }
  // Never yielding (ratio 1: a_y = r), steel at 1 m/s.
  const auto& steel = library.at("steel");
  const double t_c = model::hertz_contact_time(model::sphere_wall(steel, kRadius, steel), 1.0);
  std::vector<std::string> steps;
  for (const int per_contact : {100, 1000}) {
    auto p = law(steel, model::NormalModel::thornton_ning, t_c / per_contact);
    p.yield_ratio = {1.0, 1.0};
    steps.push_back(fmt::format(R"(    {{"steps_per_contact": {}, "e_minus_1": {:.4g}}})", per_contact, rebound(steel, p, 1.0) - 1.0));
  }
  fmt::print("{{\n  \"what\": \"a {} mm sphere on a wall of its own material, p_y = {} Y; thornton at t_c/100, "
             "thornton_ning at t_c/1000 (granstack_bench_restitution)\",\n  \"impacts\": [\n{}\n  ],\n"
             "  \"thornton_ning_elastic_steel_1ms\": [\n{}\n  ]\n}}\n",
             kRadius * 1e3, kFactor, fmt::join(rows, ",\n"), fmt::join(steps, ",\n"));
}
