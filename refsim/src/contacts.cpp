#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

namespace granstack::refsim::detail {

void PairTable::clear() {
  count = 0;
  for (auto* a : {&i, &j, &record}) a->clear();
  history.assign(history_layout(sub_models).size, {});
  touching.clear();
  records.assign(1, PairRecord{});
  model_records.assign(1, ModelRecord{});
}

void PairTable::resize(std::size_t entries, const ForShares& shares) {
  count = entries;
  for (auto* a : {&i, &j, &record}) fill_in_shares(*a, entries, 0, shares);
  history.resize(history_layout(sub_models).size);
  for (auto& a : history) fill_in_shares(a, entries, 0.0, shares);
  touching.assign(entries, 0);
}

std::pair<PairRecord, ModelRecord> PairTable::describe(const SubModels& model, double ra, double rb, double ma,
                                                       double mb, const PairConstants& k, const ModelConstants& mk) {
  const PairRecord r{ra,          rb,          ra * rb / (ra + rb), ma * mb / (ma + mb), k.kn_factor,
                     k.sn_factor, k.st_factor, k.damping_factor,    k.friction};
  return {r, model_record(model, mk, ra, r.reff, r.meff)};
}

std::int32_t RecordSet::intern(const PairRecord& r, const ModelRecord& mr) {
  std::size_t found = records.size();
  while (found > 1 && (std::memcmp(&records[found - 1], &r, sizeof r) != 0 || !(models[found - 1] == mr))) --found;
  if (found == 1) {
    records.push_back(r);
    models.push_back(mr);
    found = records.size();
  }
  return static_cast<std::int32_t>(found - 1);
}

std::vector<std::int32_t> PairTable::merge_records(const RecordSet& set) {
  RecordSet mine{records, model_records};
  std::vector<std::int32_t> number(set.records.size(), 0);
  for (std::size_t k = 1; k < set.records.size(); ++k) number[k] = mine.intern(set.records[k], set.models[k]);
  records = std::move(mine.records);
  model_records = std::move(mine.models);
  return number;
}

void PairTable::finish(const ForShares& shares) {
  const std::size_t n = padded();
  // Padding repeats the last pair at zero radius: never touching, never close, so it changes
  // nothing, and it stays within the block's windows.
  i.resize(n, count > 0 ? i[count - 1] : 0);
  j.resize(n, count > 0 ? j[count - 1] : 0);
  record.resize(n, 0);
  for (auto& a : history) a.resize(n, 0.0);
  touching.resize(n, 0);
  // Forces of one side, torques of two, and room for a 16-wide read past the last entry.
  for (auto* a : {&fx, &fy, &fz}) fill_in_shares(*a, n + static_cast<std::size_t>(kWindow), 0.0, shares);
  for (auto* a : {&tx, &ty, &tz}) fill_in_shares(*a, 2 * n + static_cast<std::size_t>(kWindow), 0.0, shares);
  forces_stored.assign(n / kPairBlock, 0);
  evaluated.assign(n / kPairBlock, 0);
  particles_i.assign(n / kLanes, 0);
  particles_j.assign(n / kLanes, 0);
  const std::size_t blocks = n / kLanes;
  window_i.assign(blocks, 0);
  window_j.assign(blocks, 0);
  fetch_i.assign(blocks, kGather);
  fetch_j.assign(blocks, kGather);
  shared_record.assign(blocks, 0);
  elastic_frictionless.assign(blocks, 0);
  // Rolling friction turns even an elastic frictionless contact's rotation into torque.
  torque_free = model.rolling == model::RollingModel::off &&
                std::all_of(record.begin(), record.end(),
                            [&](std::int32_t r) { return records[static_cast<std::size_t>(r)].elastic_frictionless(); });
  // Each block of kLanes pairs on its own, in the shares of the blocks.
  const auto describe = [&](std::size_t first_block, std::size_t end_block) {
    for (std::size_t block = first_block; block < end_block; ++block) describe_block(block);
  };
  if (shares) {
    shares(blocks, describe);
  } else {
    describe(0, blocks);
  }
}

void PairTable::describe_block(std::size_t block) {
  const std::size_t b = block * kLanes;
  const auto [i_lo, i_hi] = std::minmax_element(i.begin() + static_cast<std::ptrdiff_t>(b),
                                                i.begin() + static_cast<std::ptrdiff_t>(b + kLanes));
  const auto [j_lo, j_hi] = std::minmax_element(j.begin() + static_cast<std::ptrdiff_t>(b),
                                                j.begin() + static_cast<std::ptrdiff_t>(b + kLanes));
  window_i[block] = *i_lo;
  window_j[block] = *j_lo;
  // Padding (record 0) may take the block's shared record: its results are never summed.
  const auto first = record.begin() + static_cast<std::ptrdiff_t>(b), last = first + kLanes;
  const auto real = std::find_if(first, last, [](std::int32_t r) { return r != 0; });
  const std::int32_t shared = real == last ? 0 : *real;
  shared_record[block] = std::all_of(first, last, [&](std::int32_t r) { return r == 0 || r == shared; }) ? shared : -1;
  elastic_frictionless[block] = std::all_of(
      first, last, [&](std::int32_t r) { return records[static_cast<std::size_t>(r)].elastic_frictionless(); });
  // One side: its lanes and particles in the window, and how to fetch them. Padding lanes
  // (record 0, zero radii) never touch, whatever particles a run reads for them.
  const auto side = [&](const AlignedVector<std::int32_t>& index, std::int32_t lo, std::int32_t hi,
                        std::vector<std::uint16_t>& particles) {
    if (hi - lo >= kWindow) return kGather;
    bool run = true;
    for (std::size_t k = 0; k < kLanes; ++k) {
      const auto lane = static_cast<std::uint32_t>(index[b + k] - lo);
      particles[b / kLanes] = static_cast<std::uint16_t>(particles[b / kLanes] | 1U << lane);
      run = run && (record[b + k] == 0 || lane == k);
    }
    return run ? kRun : kWindowed;
  };
  fetch_i[block] = side(i, *i_lo, *i_hi, particles_i);
  fetch_j[block] = side(j, *j_lo, *j_hi, particles_j);
}

void SumPlan::build(const std::vector<std::size_t>& offsets,
                    const std::vector<std::pair<std::int32_t, std::uint32_t>>& contributions, std::size_t j_side,
                    const ForShares& for_shares) {
  const std::size_t n = offsets.size() - 1;
  const std::size_t groups = (n + kLanes - 1) / kLanes;
  struct Item {
    std::int64_t offset;
    std::size_t lane;
    std::uint32_t entry;
  };
  // A share of the groups planned on its own: its rounds, and per group how many and how many
  // of them subtract.
  struct Part {
    std::size_t first_group = 0;
    AlignedVector<std::uint8_t> lanes_in;
    AlignedVector<Fetch> fetch;
    std::vector<std::int32_t> window;
    AlignedVector<std::int32_t> entry;
    std::vector<std::size_t> rounds, subtracting;
  };
  std::mutex m;
  std::vector<Part> parts;
  const auto plan = [&](std::size_t first_group, std::size_t end_group) {
    Part part;
    part.first_group = first_group;
    std::vector<Item> items;
    for (std::size_t g = first_group; g < end_group; ++g) {
      items.clear();
      for (std::size_t l = 0; l < kLanes && g * kLanes + l < n; ++l) {
        const std::size_t k = g * kLanes + l;
        for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e) {
          const std::uint32_t q = contributions[e].second;  // j's (offset < 0) at j_side + p
          items.push_back({static_cast<std::int64_t>(contributions[e].first) - static_cast<std::int64_t>(k), l,
                           q >= j_side ? static_cast<std::uint32_t>(q - j_side) : q});
        }
      }
      std::sort(items.begin(), items.end(),
                [](const Item& a, const Item& b) { return a.offset != b.offset ? a.offset < b.offset : a.lane < b.lane; });
      std::uint32_t round_entry[kLanes] = {};
      unsigned in = 0;
      bool round_subtracts = false;
      std::size_t subtracting = 0;
      const std::size_t rounds_before = part.lanes_in.size();
      auto close = [&] {
        if (in == 0) return;
        std::uint32_t lo = 0xffffffffU;
        std::int64_t base = -1;  // entry - lane, if the same for every lane in the round
        bool run = true;
        for (std::size_t l = 0; l < kLanes; ++l) {
          if (in >> l & 1U) {
            lo = std::min(lo, round_entry[l]);
            const std::int64_t b = static_cast<std::int64_t>(round_entry[l]) - static_cast<std::int64_t>(l);
            run = run && (base < 0 || b == base) && b >= 0;
            base = b;
          }
        }
        part.lanes_in.push_back(static_cast<std::uint8_t>(in));
        part.fetch.push_back(run ? kRun : kGather);
        part.window.push_back(static_cast<std::int32_t>(run ? static_cast<std::uint32_t>(base) : lo));
        for (std::size_t l = 0; l < kLanes; ++l) {
          const std::uint32_t e = in >> l & 1U ? round_entry[l] : lo;  // absent lanes read a real entry, unused
          part.entry.push_back(static_cast<std::int32_t>(e));
        }
        subtracting += round_subtracts ? 1 : 0;
        in = 0;
      };
      for (std::size_t a = 0; a < items.size();) {
        std::size_t b = a;
        unsigned group = 0;
        while (b < items.size() && items[b].offset == items[a].offset) group |= 1U << items[b++].lane;
        const bool subtracts = items[a].offset < 0;
        if ((group & in) != 0 || (in != 0 && subtracts != round_subtracts)) close();
        round_subtracts = subtracts;
        for (std::size_t c = a; c < b; ++c) round_entry[items[c].lane] = items[c].entry;
        in |= group;
        a = b;
      }
      close();
      part.rounds.push_back(part.lanes_in.size() - rounds_before);
      part.subtracting.push_back(subtracting);
    }
    const std::lock_guard<std::mutex> lock(m);
    parts.push_back(std::move(part));
  };
  if (for_shares) {
    for_shares(groups, plan);
  } else {
    plan(0, groups);
  }
  // The parts one after the other, in the groups' order.
  std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) { return a.first_group < b.first_group; });
  first_round.assign(1, 0);
  first_added.clear();
  lanes_in.clear();
  fetch.clear();
  window.clear();
  entry.clear();
  for (const auto& part : parts) {
    lanes_in.insert(lanes_in.end(), part.lanes_in.begin(), part.lanes_in.end());
    fetch.insert(fetch.end(), part.fetch.begin(), part.fetch.end());
    window.insert(window.end(), part.window.begin(), part.window.end());
    entry.insert(entry.end(), part.entry.begin(), part.entry.end());
    for (std::size_t g = 0; g < part.rounds.size(); ++g) {
      first_added.push_back(first_round.back() + part.subtracting[g]);
      first_round.push_back(first_round.back() + part.rounds[g]);
    }
  }
}

void zero_contribution(PairTable& t, std::size_t p) {
  t.fx[p] = t.fy[p] = t.fz[p] = 0.0;
  for (std::size_t q : {p, t.padded() + p}) t.tx[q] = t.ty[q] = t.tz[q] = 0.0;
}

ContactEnergy pair_contact_energy(const PairTable& t, std::size_t p, double overlap) {
  double history[kMaxHistory];
  for (std::size_t k = 0; k < t.history.size(); ++k) history[k] = t.history[k][p];
  return contact_energy(t.sub_models, t.model_records[static_cast<std::size_t>(t.record[p])], overlap, history);
}

void bank_opened(const PairTable& t, double* banked, std::size_t p) {
  const double work = pair_contact_energy(t, p, 0.0).dissipated;
  bank_work(banked, static_cast<std::size_t>(t.i[p]), 0.5 * work);
  bank_work(banked, static_cast<std::size_t>(t.j[p]), 0.5 * work);
}

namespace {

// Pair p's contact, composed of the table's sub-models, into entry p.
void pair_force(PairTable& t, const ContactStep& s, std::size_t p) {
  const PairPoint point = pair_point(t.sub_models.frame, t, s, p);
  if (!point.touching) {
    if (point.forget) {
      if (s.banked && t.touching[p]) bank_opened(t, s.banked, p);
      t.touching[p] = 0;
      for (auto& h : t.history) h[p] = 0.0;
    }
    zero_contribution(t, p);
    return;
  }
  t.touching[p] = 1;
  const ContactPoint& c = point.c;
  const std::size_t record = static_cast<std::size_t>(t.record[p]);
  double history[kMaxHistory];
  for (std::size_t k = 0; k < t.history.size(); ++k) history[k] = t.history[k][p];
  const ContactForces out = contact(t.sub_models, t.records[record].constants(), t.model_records[record], c, history,
                                    s.update_history, s.tangential_damping, s.dt);
  for (std::size_t k = 0; k < t.history.size(); ++k) t.history[k][p] = history[k];
  // The force on j is (0 + -fn en) + -ft, the exact negative of this but for the sign of a zero
  // (which a sum that starts at +0 never shows): the sums subtract this.
  const std::size_t q = t.padded() + p;
  t.fx[p] = out.n.fn * c.en[0] + out.ft[0];
  t.fy[p] = out.n.fn * c.en[1] + out.ft[1];
  t.fz[p] = out.n.fn * c.en[2] + out.ft[2];
  t.tx[p] = -c.arm_i * out.tor[0];
  t.ty[p] = -c.arm_i * out.tor[1];
  t.tz[p] = -c.arm_i * out.tor[2];
  t.tx[q] = -c.arm_j * out.tor[0];
  t.ty[q] = -c.arm_j * out.tor[1];
  t.tz[q] = -c.arm_j * out.tor[2];
  if (out.rolling) {  // minus the torque on i, plus on j
    t.tx[p] -= out.rt[0];
    t.ty[p] -= out.rt[1];
    t.tz[p] -= out.rt[2];
    t.tx[q] += out.rt[0];
    t.ty[q] += out.rt[1];
    t.tz[q] += out.rt[2];
  }
}

}  // namespace

void contacts_reference(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end) {
  for (std::size_t p = begin; p < end; ++p) pair_force(pairs, s, p);
}

bool first_half_reference(const Motion& m, std::size_t begin, std::size_t end) {
  bool moved = false;
  const std::size_t y = m.stride, z = 2 * m.stride;
  for (std::size_t i = begin; i < end; ++i) {
    for (std::size_t e : {i, y + i, z + i}) {
      m.v[e] += m.kick[i] * m.f[e];
      m.x[e] += m.dt * m.v[e];
      m.w[e] += m.spin_kick[i] * m.t[e];
    }
    const double dx = m.x[i] - m.x_at_build[i];
    const double dy = m.x[y + i] - m.x_at_build[y + i];
    const double dz = m.x[z + i] - m.x_at_build[z + i];
    moved |= dx * dx + dy * dy + dz * dz > m.trigger;
  }
  return moved;
}

void second_half_reference(const Motion& m, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    for (std::size_t e : {i, m.stride + i, 2 * m.stride + i}) {
      m.v[e] += m.kick[i] * m.f[e];
      m.w[e] += m.spin_kick[i] * m.t[e];
    }
  }
}

void kinetic_sums_reference(const KineticInput& in, std::size_t begin, std::size_t end, double* translational,
                            double* rotational) {
  const std::size_t y = in.stride, z = 2 * in.stride;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t k = (i - begin) % kLanes;
    translational[k] += in.mass[i] * (in.v[i] * in.v[i] + in.v[y + i] * in.v[y + i] + in.v[z + i] * in.v[z + i]);
    rotational[k] += (in.w[i] * in.w[i] + in.w[y + i] * in.w[y + i] + in.w[z + i] * in.w[z + i]) * in.radius[i] * in.radius[i] * in.mass[i];
  }
}

}  // namespace granstack::refsim::detail
