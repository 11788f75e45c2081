// refsim's pair table: the candidate pairs found at a neighbour build, their histories carried
// across it, grouped by tile in LIGGGHTS's pair order, and each particle's contributions listed.
#include <granstack/refsim/neighbors.hpp>
#include <granstack/refsim/system.hpp>

#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace granstack::refsim {

namespace {

struct Candidate {
  std::int32_t i, j;
  bool touching;
};
// Per candidate, the entry of the table before the rebuild whose history it keeps, or kNone.
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

// The table's entries: the candidates in `order`, each tile's group padded to whole kernel
// blocks (padding repeats the group's last pair with record 0), filled in the shares of the
// groups. Each share numbers the records it meets; the table's numbers are then given in the
// groups' order, as one pass through the table gives them. describe(i, j) gives a pair's records.
// Returns where each group starts in the table, and the table's end.
template <class Describe>
std::vector<std::size_t> fill_table(detail::PairTable& pairs, const std::vector<Candidate>& found, const std::vector<std::size_t>& order,
                const std::vector<std::size_t>& tile_start, const detail::PairTable& old, const std::vector<std::size_t>& kept, const ForShares& shares,
                Describe describe) {
  const std::size_t groups = tile_start.size() - 1;
  std::vector<std::size_t> entry_start(groups + 1, 0);
  for (std::size_t g = 0; g < groups; ++g) {
    entry_start[g + 1] = entry_start[g] + (tile_start[g + 1] - tile_start[g] + detail::kPairBlock - 1) / detail::kPairBlock * detail::kPairBlock;
  }
  pairs.resize(entry_start[groups], shares);
  struct Local {
    std::size_t first_group = 0, end_group = 0;
    detail::RecordSet records;  // its padding record first, as the table's
  };
  std::mutex m;
  std::vector<Local> locals;
  shares(groups, [&](std::size_t first_group, std::size_t end_group) {
    Local local{first_group, end_group, {}};
    for (std::size_t g = first_group; g < end_group; ++g) {
      std::size_t q = entry_start[g];
      for (std::size_t c = tile_start[g]; c < tile_start[g + 1]; ++c, ++q) {
        const auto& f = found[order[c]];
        pairs.i[q] = f.i;
        pairs.j[q] = f.j;
        const auto [r, mr] = describe(static_cast<std::size_t>(f.i), static_cast<std::size_t>(f.j));
        pairs.record[q] = local.records.intern(r, mr);
        if (!kept.empty() && kept[order[c]] != kNone) {
          const std::size_t from = kept[order[c]];
          pairs.touching[q] = 1;
          for (std::size_t h = 0; h < pairs.history.size(); ++h) pairs.history[h][q] = old.history[h][from];
        }
      }
      for (; q < entry_start[g + 1]; ++q) {  // padding
        pairs.i[q] = pairs.i[q - 1];
        pairs.j[q] = pairs.j[q - 1];
      }
    }
    const std::lock_guard<std::mutex> lock(m);
    locals.push_back(std::move(local));
  });
  std::sort(locals.begin(), locals.end(), [](const Local& a, const Local& b) { return a.first_group < b.first_group; });
  std::vector<std::vector<std::int32_t>> renumber;
  for (const auto& local : locals) renumber.push_back(pairs.merge_records(local.records));
  shares(locals.size(), [&](std::size_t first, std::size_t end) {
    for (std::size_t l = first; l < end; ++l) {
      for (std::size_t q = entry_start[locals[l].first_group]; q < entry_start[locals[l].end_group]; ++q) {
        pairs.record[q] = renumber[l][static_cast<std::size_t>(pairs.record[q])];
      }
    }
  });
  return entry_start;
}

// The history each candidate keeps from the table before the rebuild: a pair keeps it only if it
// was flagged as touching and is within the contact distance now (none at the first build).
std::vector<std::size_t> kept_history(const detail::PairTable& old, const std::vector<Candidate>& found) {
  std::vector<std::size_t> old_order;
  for (std::size_t q = 0; q < old.count; ++q) {
    if (old.record[q] != 0) old_order.push_back(q);  // padding has record 0
  }
  if (old_order.empty()) return {};
  std::sort(old_order.begin(), old_order.end(),
            [&](std::size_t a, std::size_t b) { return old.i[a] != old.i[b] ? old.i[a] < old.i[b] : old.j[a] < old.j[b]; });
  std::vector<std::size_t> kept(found.size(), kNone);
  for (std::size_t c = 0, o = 0; c < found.size(); ++c) {
    const auto& f = found[c];
    while (o < old_order.size() && (old.i[old_order[o]] < f.i || (old.i[old_order[o]] == f.i && old.j[old_order[o]] < f.j))) ++o;
    const std::size_t q = o < old_order.size() ? old_order[o] : 0;
    if (o < old_order.size() && old.i[q] == f.i && old.j[q] == f.j && old.touching[q] && f.touching) {
      kept[c] = q;
    }
  }
  return kept;
}

// The table's order of the candidates: by tile of i, then j - i, then i, so that a block's
// particles lie in a window (tiles of tile_size particles). The candidates come in (i, j) order,
// so each tile's are together (tile_start gets where each tile's group starts, and their end), and
// each is sorted on its own.
std::vector<std::size_t> table_order(const std::vector<Candidate>& found, std::size_t tile_size, const ForShares& shares,
                                     std::vector<std::size_t>& tile_start) {
  std::vector<std::size_t> order(found.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  const auto tile = [&](std::int32_t i) { return static_cast<std::size_t>(i) / tile_size; };
  tile_start.clear();
  for (std::size_t c = 0; c < found.size(); ++c) {
    if (c == 0 || tile(found[c].i) != tile(found[c - 1].i)) tile_start.push_back(c);
  }
  tile_start.push_back(found.size());
  shares(tile_start.size() - 1, [&](std::size_t first_tile, std::size_t end_tile) {
    for (std::size_t t = first_tile; t < end_tile; ++t) {
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(tile_start[t]),
                order.begin() + static_cast<std::ptrdiff_t>(tile_start[t + 1]), [&](std::size_t a, std::size_t b) {
                  const auto &u = found[a], &v = found[b];
                  return u.j - u.i != v.j - v.i ? u.j - u.i < v.j - v.i : u.i < v.i;
                });
    }
  });
  return order;
}

// Each particle's contributions in LIGGGHTS's pair order, by the other particle's index (counted,
// placed, then each particle's sorted in the shares): particle k's are contributions[offsets[k]
// .. offsets[k + 1]], j's entries at padded() + p.
void list_contributions(const detail::PairTable& pairs, std::size_t n, const ForShares& shares,
                        std::vector<std::size_t>& offsets, std::vector<std::pair<std::int32_t, std::uint32_t>>& contributions) {
  const std::size_t side_j = pairs.padded();
  offsets.assign(n + 1, 0);
  for (std::size_t p = 0; p < pairs.count; ++p) {
    if (pairs.record[p] == 0) continue;  // padding
    ++offsets[static_cast<std::size_t>(pairs.i[p]) + 1];
    ++offsets[static_cast<std::size_t>(pairs.j[p]) + 1];
  }
  for (std::size_t k = 0; k < n; ++k) offsets[k + 1] += offsets[k];
  contributions.resize(offsets[n]);
  std::vector<std::size_t> next(offsets.begin(), offsets.end() - 1);
  for (std::size_t p = 0; p < pairs.count; ++p) {
    if (pairs.record[p] == 0) continue;
    contributions[next[static_cast<std::size_t>(pairs.i[p])]++] = {pairs.j[p], static_cast<std::uint32_t>(p)};
    contributions[next[static_cast<std::size_t>(pairs.j[p])]++] = {pairs.i[p], static_cast<std::uint32_t>(side_j + p)};
  }
  shares(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      std::sort(contributions.begin() + static_cast<std::ptrdiff_t>(offsets[k]),
                contributions.begin() + static_cast<std::ptrdiff_t>(offsets[k + 1]));
    }
  });
}

}  // namespace

// The work of the old table's contacts that lose their history at this rebuild (flagged as
// touching, beyond the contact distance now), banked as their opening banks it.
void System::bank_lost_pairs(const detail::PairTable& old, const std::vector<std::size_t>& kept) {
  std::vector<char> carried(old.count, 0);
  for (const std::size_t q : kept) {
    if (q != kNone) carried[q] = 1;
  }
  for (std::size_t q = 0; q < old.count; ++q) {
    if (old.record[q] != 0 && old.touching[q] && !carried[q]) detail::bank_opened(old, banked_.data(), q);
  }
}

void System::build_pairs() {
  // Candidates: (R_i + R_j) * cdf + skin, as neigh_gran.cpp. A pair keeps its history across
  // the rebuild only if it was flagged as touching and is within the contact distance now.
  std::vector<Candidate> found;
  const double cdf = p_.contact_distance_factor;
  const double* x = x_.data();
  const double* y = x + stride_;
  const double* z = y + stride_;
  const auto shares = [this](std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) {
    for_shares(count, job, 1);
  };
  const auto candidates = candidate_pairs({x, y, z, radius_.data(), n_}, cdf, p_.skin, shares);
  found.reserve(candidates.size());
  for (const auto& [a, b] : candidates) {
    const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
    const double delx = x[i] - x[j];
    const double dely = y[i] - y[j];
    const double delz = z[i] - z[j];
    const double rsq = delx * delx + dely * dely + delz * delz;
    const double radsum = (radius_[i] + radius_[j]) * cdf;
    found.push_back({a, b, rsq < radsum * radsum});
  }
  // The history of the old pairs, merged in (i, j) order.
  detail::PairTable old;
  std::swap(old, *pairs_);
  const auto kept = kept_history(old, found);
  if (!banked_.empty()) bank_lost_pairs(old, kept);
  std::vector<std::size_t> tile_start;
  const auto order = table_order(found, kTile, shares, tile_start);
  const auto tile = [](std::int32_t i) { return static_cast<std::size_t>(i) / kTile; };
  pairs_->clear();
  pairs_->model = p_.contact;
  pairs_->sub_models = old.sub_models;
  const auto entry_start = fill_table(*pairs_, found, order, tile_start, old, kept, shares, [&](std::size_t i, std::size_t j) {
    const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                  static_cast<std::size_t>(type_[j] - 1);
    return detail::PairTable::describe(pairs_->sub_models, radius_[i], radius_[j], mass_[i], mass_[j], type_constants_[type_pair],
                                       model_constants_[type_pair]);
  });
  // Where each tile's pairs start (a tile without pairs where the next one's do).
  tile_first_.assign(1, 0);
  for (std::size_t g = 0; g + 1 < tile_start.size(); ++g) {
    while (tile_first_.size() <= tile(found[tile_start[g]].i)) tile_first_.push_back(entry_start[g]);
  }
  while (tile_first_.size() <= (n_ + kTile - 1) / kTile) tile_first_.push_back(pairs_->count);
  auto& pairs = *pairs_;
  pairs.finish(shares);
  const std::size_t side_j = pairs.padded();
  list_contributions(pairs, n_, shares, contribution_offsets_, contributions_);
  if (vector_) {
    sum_plan_->build(contribution_offsets_, contributions_, side_j, shares);
  }
  x_at_build_ = x_;
  plate_body_at_build_ = plate_body_;
  find_wall_candidates();
  ++builds_;
}

}  // namespace granstack::refsim
