#pragma once
// What the kernel tests share with the emulated check of the ARM kernels, which runs without
// the rest of granstack: the comparison of two systems to the bit, and a kernel case (its
// parameters and particles) as a text file, every double in hexadecimal, which reads back to
// the same bits. Header only: the ARM build compiles it with refsim's system sources alone.
#include <granstack/refsim/system.hpp>

#include <cstdlib>
#include <fstream>
#include <ios>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granstack::test_support {

// "" if `a` holds the reference's state to the bit (positions, velocities, spins, forces,
// torques, the series' energies of whole and partial groups, steps and neighbour builds), else
// the first difference.
inline std::string first_difference(const refsim::System& a, const refsim::System& reference) {
  std::ostringstream out;
  out << std::hexfloat;
  const auto differ = [&](const char* what, std::size_t i, const refsim::Vec3& x, const refsim::Vec3& y) {
    if (x == y) return false;
    out << a.kernel() << ", sphere " << i << ": " << what << " (" << x[0] << ", " << x[1] << ", " << x[2] << ") against ("
        << y[0] << ", " << y[1] << ", " << y[2] << ")";
    return true;
  };
  if (a.step_count() != reference.step_count() || a.neighbor_builds() != reference.neighbor_builds()) {
    out << a.kernel() << ": " << a.step_count() << " steps and " << a.neighbor_builds() << " neighbour builds against "
        << reference.step_count() << " and " << reference.neighbor_builds();
    return out.str();
  }
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (differ("position", i, a.x(i), reference.x(i)) || differ("velocity", i, a.v(i), reference.v(i)) ||
        differ("spin", i, a.omega(i), reference.omega(i)) || differ("force", i, a.force(i), reference.force(i)) ||
        differ("torque", i, a.torque(i), reference.torque(i))) {
      return out.str();
    }
  }
  const std::size_t n = reference.size();
  for (const auto& [begin, end] : {std::pair<std::size_t, std::size_t>{0, n}, {3, 17}, {5, 6}, {9, n - 2}, {n - 1, n}}) {
    const auto x = a.kinetic_energy(begin, end), y = reference.kinetic_energy(begin, end);
    if (x != y) {
      out << a.kernel() << ": kinetic energies of spheres " << begin << ".." << end << " (" << x[0] << ", " << x[1]
          << ") against (" << y[0] << ", " << y[1] << ")";
      return out.str();
    }
  }
  return "";
}

// The kernel tests' run: the start-of-run force call, then 3000 steps one at a time, or through
// advance() taking each step's end and the next one's start together.
inline std::unique_ptr<refsim::System> run_3000_steps(const std::vector<refsim::Particle>& particles,
                                                      const refsim::Parameters& params, bool advance) {
  auto s = std::make_unique<refsim::System>(particles, params);
  s->setup();
  if (advance) {
    s->advance(1000);
    s->advance(2000);
  } else {
    for (int k = 0; k < 3000; ++k) s->step();
  }
  return s;
}

struct KernelCaseFile {
  refsim::Parameters params;
  std::vector<refsim::Particle> particles;
  std::size_t output = 0;  // the output sphere's index: the pulse must have got there
};

inline void write_kernel_case(const std::string& path, const KernelCaseFile& c) {
  std::ofstream out(path);
  out << std::hexfloat;
  const auto& p = c.params;
  out << "granstack-kernel-case 1\noutput " << c.output << "\n";
  out << "dt " << p.dt << " skin " << p.skin << " contact_distance_factor " << p.contact_distance_factor << " gravity "
      << p.gravity[0] << " " << p.gravity[1] << " " << p.gravity[2] << " tangential_damping " << p.tangential_damping
      << "\ntypes " << p.types << "\n";
  for (const auto* table : {&p.y_star, &p.g_star, &p.beta, &p.friction}) {
    for (const double v : *table) out << v << " ";
    out << "\n";
  }
  out << "walls " << p.walls.size() << "\n";
  for (const auto& w : p.walls) out << w.axis << " " << w.position << " " << w.type << "\n";
  out << "particles " << c.particles.size() << "\n";
  for (const auto& q : c.particles) {
    out << q.type << " " << q.radius << " " << q.mass;
    for (const auto* v : {&q.x, &q.v, &q.omega}) out << " " << (*v)[0] << " " << (*v)[1] << " " << (*v)[2];
    out << "\n";
  }
  if (!out) throw std::runtime_error(path + ": cannot write");
}

inline KernelCaseFile read_kernel_case(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  const auto expect = [&](const char* name) {
    if (!(in >> word) || word != name) throw std::runtime_error(path + ": expected '" + name + "', found '" + word + "'");
  };
  // Hexadecimal doubles through strtod (streams do not read them back everywhere).
  const auto number = [&] {
    if (!(in >> word)) throw std::runtime_error(path + ": file ends early");
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (end != word.c_str() + word.size()) throw std::runtime_error(path + ": '" + word + "' is not a number");
    return v;
  };
  const auto count = [&] { return static_cast<std::size_t>(number()); };
  KernelCaseFile c;
  auto& p = c.params;
  expect("granstack-kernel-case");
  expect("1");
  expect("output");
  c.output = count();
  expect("dt");
  p.dt = number();
  expect("skin");
  p.skin = number();
  expect("contact_distance_factor");
  p.contact_distance_factor = number();
  expect("gravity");
  for (double& g : p.gravity) g = number();
  expect("tangential_damping");
  p.tangential_damping = number() != 0.0;
  expect("types");
  p.types = static_cast<int>(count());
  for (auto* table : {&p.y_star, &p.g_star, &p.beta, &p.friction}) {
    table->resize(static_cast<std::size_t>(p.types * p.types));
    for (double& v : *table) v = number();
  }
  expect("walls");
  p.walls.resize(count());
  for (auto& w : p.walls) {
    w.axis = static_cast<int>(number());
    w.position = number();
    w.type = static_cast<int>(number());
  }
  expect("particles");
  c.particles.resize(count());
  for (auto& q : c.particles) {
    q.type = static_cast<int>(number());
    q.radius = number();
    q.mass = number();
    for (auto* v : {&q.x, &q.v, &q.omega}) {
      for (double& d : *v) d = number();
    }
  }
  return c;
}

}  // namespace granstack::test_support
