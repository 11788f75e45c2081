// The search's encoding of a design: a vector of genes (the number of blocks, each block's
// material, the radius ratio below it and its rows) decoded into a spec and back, the box the
// genes lie in, the space's extreme designs, and a spec's canonical form, digest and description.
#include <granstack/design/space.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace granstack::design {

std::pair<std::vector<double>, std::vector<double>> Space::bounds() const {
  std::vector<double> lo(genes(), 0.0), hi(genes(), 0.0);
  lo[0] = min_blocks;
  hi[0] = max_blocks;
  for (int k = 0; k < max_blocks; ++k) {
    const auto m = static_cast<std::size_t>(1 + k), r = static_cast<std::size_t>(1 + max_blocks + k),
               n = static_cast<std::size_t>(2 * max_blocks + k);
    hi[m] = static_cast<double>(materials.size() - 1);
    if (k + 1 < max_blocks) hi[r] = static_cast<double>(radius_ratios.size() - 1);
    lo[n] = min_rows;
    hi[n] = max_rows;
  }
  for (std::size_t i = 0; i < hi.size(); ++i) hi[i] = std::max(hi[i], lo[i] + 1.0);
  return {lo, hi};
}

model::StackSpec Space::decode(const std::vector<double>& x) const {
  auto gene = [&](std::size_t i) { return static_cast<int>(std::lround(x.at(i))); };
  model::StackSpec s = fixed;
  s.blocks = std::clamp(gene(0), min_blocks, max_blocks);
  s.materials.clear();
  s.radius_ratios.clear();
  s.block_rows.clear();
  const auto pick = [&](const auto& choices, std::size_t i) {
    return choices.at(static_cast<std::size_t>(std::clamp(gene(i), 0, static_cast<int>(choices.size()) - 1)));
  };
  for (int k = 0; k < s.blocks; ++k) {
    s.materials.push_back(pick(materials, static_cast<std::size_t>(1 + k)));
    if (k + 1 < s.blocks) s.radius_ratios.push_back(pick(radius_ratios, static_cast<std::size_t>(1 + max_blocks + k)));
    s.block_rows.push_back(std::clamp(gene(static_cast<std::size_t>(2 * max_blocks + k)), min_rows, max_rows));
  }
  // The footprint stays: R_1 = top_radius, so the bottom radius is R_1 over the ratios' product.
  double factor = 1.0;
  for (const int r : s.radius_ratios) factor *= r;
  s.bottom_radius = top_radius / factor;
  if (s.radius_ratios.empty()) s.radius_ratio = fixed.radius_ratio;
  return canonical(std::move(s));
}

std::optional<std::vector<double>> Space::encode(const model::StackSpec& spec) const {
  if (spec.blocks < min_blocks || spec.blocks > max_blocks) return std::nullopt;
  std::vector<double> x(genes(), 0.0);
  x[0] = spec.blocks;
  const auto index = [](const auto& choices, const auto& value) -> std::optional<double> {
    const auto at = std::find(choices.begin(), choices.end(), value);
    if (at == choices.end()) return std::nullopt;
    return static_cast<double>(at - choices.begin());
  };
  for (int k = 0; k < max_blocks; ++k) {
    const int block = std::min(k + 1, spec.blocks);  // past N_B: the last block's genes
    const auto m = index(materials, spec.block_material(block));
    const int rows = spec.rows_of(block);
    if (!m || rows < min_rows || rows > max_rows) return std::nullopt;
    x[static_cast<std::size_t>(1 + k)] = *m;
    x[static_cast<std::size_t>(2 * max_blocks + k)] = rows;
    if (k + 1 == max_blocks) continue;
    const auto r = spec.blocks > 1 ? index(radius_ratios, spec.ratio_below(std::min(k + 1, spec.blocks - 1))) : std::optional<double>(0.0);
    if (!r) return std::nullopt;
    x[static_cast<std::size_t>(1 + max_blocks + k)] = *r;
  }
  return x;
}

std::pair<model::StackSpec, model::StackSpec> Space::extreme_designs() const {
  const auto lib = fixed.material_library();
  std::size_t light = 0, dense = 0;
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const auto* a = lib.find(materials[m]);
    if (a == nullptr) continue;
    if (a->density < lib.at(materials[light]).density) light = m;
    if (a->density > lib.at(materials[dense]).density) dense = m;
  }
  const auto corner = [&](int blocks, std::size_t material, std::size_t ratio, int rows) {
    std::vector<double> x(genes(), 0.0);
    x[0] = blocks;
    for (int k = 0; k < max_blocks; ++k) {
      x[static_cast<std::size_t>(1 + k)] = static_cast<double>(material);
      if (k + 1 < max_blocks) x[static_cast<std::size_t>(1 + max_blocks + k)] = static_cast<double>(ratio);
      x[static_cast<std::size_t>(2 * max_blocks + k)] = rows;
    }
    return decode(x);
  };
  return {corner(min_blocks, light, radius_ratios.size() - 1, min_rows), corner(max_blocks, dense, 0, max_rows)};
}

model::StackSpec canonical(model::StackSpec spec) {
  const auto same = [](const std::vector<int>& v) { return !v.empty() && std::all_of(v.begin(), v.end(), [&](int x) { return x == v.front(); }); };
  if (same(spec.radius_ratios)) {
    spec.radius_ratio = spec.radius_ratios.front();
    spec.radius_ratios.clear();
  }
  if (same(spec.block_rows)) {
    spec.rows = spec.block_rows.front();
    spec.block_rows.clear();
  }
  return spec;
}

std::string spec_digest(const model::StackSpec& spec) { return formats::sha256_hex(model::spec_json(spec).dump()); }

std::string describe(const model::StackSpec& spec) {
  std::vector<int> rows;
  for (int k = 1; k <= spec.blocks; ++k) rows.push_back(spec.rows_of(k));
  std::vector<int> ratios;
  for (int k = 1; k < spec.blocks; ++k) ratios.push_back(spec.ratio_below(k));
  return fmt::format("{}, ratios {}, rows {}", fmt::join(spec.materials, "/"), ratios.empty() ? "-" : fmt::format("{}", fmt::join(ratios, "/")),
                     fmt::join(rows, "/"));
}

}  // namespace granstack::design
