#include "kernel_cases.hpp"

#include <granstack/generator/case_writer.hpp>
#include <granstack/refsim/case_run.hpp>

#include <algorithm>
#include <utility>

namespace granstack::test_support {

std::vector<KernelCase> kernel_cases() {
  std::vector<KernelCase> cases;
  for (const auto& [frictional, reversed] : {std::pair{true, false}, {false, false}, {false, true}}) {
    model::StackSpec spec;
    spec.blocks = 3;
    spec.top_columns = 4;
    spec.restitution.value = frictional ? 0.9 : 1.0;
    spec.friction.value = frictional ? 0.25 : 0.0;
    // Elastic frictionless without walls: no torque anywhere, the spins are left alone.
    spec.bottom = frictional ? model::Boundary::wall : model::Boundary::free_surface;
    spec.sides = frictional ? model::Boundary::wall : model::Boundary::free_surface;
    spec.gravity = frictional ? 9.80665 : 0.0;
    spec.striker_speed = 20.0;  // fast enough to move spheres half a skin: rebuilds
    const auto stack = model::Stack::build(spec);
    auto particles = refsim::particles_from(generator::data_file(stack, "kernels"));
    if (reversed) std::reverse(particles.begin(), particles.end());
    const std::size_t output = reversed ? particles.size() - stack.output_sphere_id() : stack.output_sphere_id() - 1;
    const std::string name = frictional ? "damped_frictional_walls_gravity" : reversed ? "elastic_reversed" : "elastic";
    cases.push_back({name, stack, particles, output});
  }
  return cases;
}

}  // namespace granstack::test_support
