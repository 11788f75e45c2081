// The asynchronous search (search.hpp, run_asynchronous): a steady-state NSGA-II whose designs
// run on a pool of threads, a new one started whenever one ends.
#include "screening.hpp"
#include "survival.hpp"

#include <granstack/design/convergence.hpp>
#include <granstack/design/search.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>
#include <pagmo/utils/genetic_operators.hpp>
#include <pagmo/utils/multi_objective.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <numeric>
#include <random>
#include <set>

namespace granstack::design {

namespace {

using Clock = std::chrono::steady_clock;

// MOEA/D's settings (Zhang and Li 2007; Li and Zhang 2009's replacement bound).
constexpr std::size_t kMoeadNeighbours = 20;
constexpr double kMoeadLocalMating = 0.9;

struct Member {
  std::vector<double> x;  // canonical genes
  std::string digest;
  std::vector<double> f;  // fitness() in the normalised box
};

// A design to run, and what its run gave.
struct Job {
  std::vector<double> x;
  model::StackSpec spec;
  std::optional<Probe> probe;  // a probe: run even outside the constraints, stored apart
  std::optional<Evaluation> ready;  // run before (by another seed's run): joins without running
  std::size_t subproblem = 0;        // MOEA/D: the weight it was bred for
};
struct Finished {
  Job job;
  std::optional<Evaluation> evaluation;
  std::exception_ptr error;
};

// The designs to run and those that ran, between the search and the threads of an os::Workers
// that each run work(), one design at a time (in situ on refsim, one core; or through the
// search's runner, e.g. as a SLURM job array). The search starts a design only when a thread is
// free, and takes the finished ones back in the order they finished.
class Pool {
 public:
  Pool(const Space& space, BatchRunner* runner, Dominator dominator)
      : space_(space), runner_(runner), dominator_(std::move(dominator)) {}
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;
  // Ends every work(): nothing more starts, and a design still running is abandoned (its run
  // stops at its next look).
  void close() {
    {
      const std::lock_guard<std::mutex> lock(m_);
      closing_ = true;
      queue_.clear();
    }
    abandon_ = true;
    work_cv_.notify_all();
  }
  void start(Job job) {
    {
      const std::lock_guard<std::mutex> lock(m_);
      queue_.push_back(std::move(job));
      ++running_;
    }
    work_cv_.notify_one();
  }
  // The designs finished since the last call, waiting up to `up_to` for one.
  std::vector<Finished> finished(std::chrono::milliseconds up_to) {
    std::unique_lock<std::mutex> lock(m_);
    done_cv_.wait_for(lock, up_to, [&] { return !done_.empty(); });
    std::vector<Finished> out;
    out.swap(done_);
    running_ -= static_cast<int>(out.size());
    return out;
  }
  int running() {
    const std::lock_guard<std::mutex> lock(m_);
    return running_;
  }
  // A thread's loop: runs the designs started, one at a time, until close().
  void work() {
    for (;;) {
      Job job;
      {
        std::unique_lock<std::mutex> lock(m_);
        work_cv_.wait(lock, [&] { return closing_ || !queue_.empty(); });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      Finished f{std::move(job), std::nullopt, nullptr};
      try {
        const bool run_anyway = f.job.probe.has_value();
        f.evaluation = runner_ != nullptr ? runner_->evaluate_one(space_, f.job.spec, run_anyway, &abandon_, dominator_)
                                          : evaluate_design(space_, f.job.spec, run_anyway, &abandon_, dominator_);
      } catch (...) {
        f.error = std::current_exception();
      }
      {
        const std::lock_guard<std::mutex> lock(m_);
        done_.push_back(std::move(f));
      }
      done_cv_.notify_one();
    }
  }

 private:
  const Space& space_;
  BatchRunner* runner_;
  Dominator dominator_;
  std::mutex m_;
  std::condition_variable work_cv_, done_cv_;
  std::deque<Job> queue_;
  std::vector<Finished> done_;
  int running_ = 0;
  bool closing_ = false;
  std::atomic<bool> abandon_{false};
};

// Design number `n`'s own random stream, from the search's seed.
std::mt19937 stream(std::uint64_t seed, long n) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(n),
                    static_cast<std::uint32_t>(static_cast<std::uint64_t>(n) >> 32), 0x61737963u};
  return std::mt19937(seq);
}

class Asynchronous {
 public:
  Asynchronous(const Space& space, Store& store, const SearchOptions& options, int run)
      : space_(space), store_(store), options_(options), run_(run), seed_(space.search.seeds.at(static_cast<std::size_t>(run))),
        norm_(stored_normalisation(store)), bounds_(space.bounds()),
        population_(static_cast<std::size_t>(space.search.population)) {}

  SearchResult run();
  void search(Pool& pool, int jobs, std::exception_ptr& error);

 private:
  void replay();
  // `subproblem`: MOEA/D's weight the design was bred for (its draw's number modulo the population).
  void join(const Evaluation& e, bool replaying, std::size_t subproblem = 0);
  void survive(Member m, std::size_t subproblem);
  void decompose();
  void record_generation(int index);
  std::optional<Job> draw();
  std::vector<double> bred(std::mt19937& rng, std::size_t subproblem) const;
  std::vector<double> uniform(std::mt19937& rng) const;
  std::optional<Job> screened(std::mt19937& rng, std::size_t subproblem);
  bool may_start(int searching);
  bool rejected(const Geometry& g);
  bool rejected(const model::StackSpec& spec) { return rejected(measure(space_, spec)); }
  // The store's evaluation of a design where it stands for this run (stands_for), else none: it runs.
  std::optional<Evaluation> standing(const std::string& digest) {
    auto e = store_.find(digest);
    if (e && !stands_for(*e, space_, [this](const std::vector<double>& v) { return dominated(v); })) return std::nullopt;
    return e;
  }
  std::map<std::string, long> rejections_;  // constraint broken -> draws it refused
  long limit() const;
  long finished() const { return static_cast<long>(archive_.size() + held_.size()) + (norm_ ? 0 : warm_expected_); }
  void take(std::vector<Finished> done, std::exception_ptr& error);
  void joined(const Evaluation& e, bool stored, std::size_t subproblem);
  void start_probes(Pool& pool);
  void probe_done(const Finished& f);

  const Space& space_;
  Store& store_;
  const SearchOptions& options_;
  int run_;
  std::uint64_t seed_;
  std::optional<Normalisation> norm_;  // none until the probes have run
  int probes_running_ = 0;
  long warm_expected_ = 0;             // probes that are designs of the space, before they ran
  std::vector<std::vector<double>> weights_;            // MOEA/D: a weight per member
  std::vector<std::vector<std::size_t>> neighbours_;    // MOEA/D: each weight's nearest, itself first
  std::vector<std::pair<Evaluation, std::size_t>> held_;  // ended before the box was fixed, in order
  std::pair<std::vector<double>, std::vector<double>> bounds_;
  std::size_t population_;
  std::vector<Member> members_;
  std::vector<Evaluation> archive_;  // the designs the search has joined, in order
  std::vector<Evaluation> front_;    // the archive's feasible designs no other dominates
  Screening screening_{space_};      // the archive's genes and points, for [search] screening
  // The front as the shortcuts ask it (from the pool's threads while designs join): rebuilt as it changes.
  std::optional<std::string> dominated(const std::vector<double>& v) {
    Dominator d;
    {
      const std::lock_guard<std::mutex> lock(front_m_);
      d = front_dominator_;
    }
    return d ? d(v) : std::nullopt;
  }
  std::mutex front_m_;
  Dominator front_dominator_;
  std::set<std::string> known_;      // stored, running or rejected: never drawn again
  long drawn_ = 0;                   // designs started, over every call (the random streams' numbers)
  int last_generation_ = -1;
  std::vector<double> hypervolumes_;
  std::string ended_;
  Clock::time_point deadline_ = Clock::time_point::max();
  SearchResult result_;
};

void Asynchronous::replay() {
  std::set<std::string> probes;
  for (const auto& p : probe_designs(space_)) probes.insert(spec_digest(p.spec));
  known_ = probes;
  if (!norm_) return;  // nothing joined before the box
  const auto joins = store_.joins(run_);
  for (const auto& digest : joins) {
    const auto e = store_.find(digest);
    if (!e) throw StoreError(fmt::format("the store's run {} joined design {}, which it does not hold", run_, digest.substr(0, 12)));
    join(*e, true, static_cast<std::size_t>(drawn_) % population_);
    drawn_ += probes.count(digest) == 0;  // the probes that began the search were not drawn
  }
  if (joins.empty()) {  // a later seed's run: it begins with the probes that are designs of the space, as the first did
    for (const auto& e : warm_designs(space_, store_)) join(e, false);
  }
  if (const auto g = store_.last_generation(run_)) last_generation_ = g->index;
  result_.first_generation = last_generation_ + 1;
}

// A member joins the population: it drops its worst (NSGA-II, NSGA-III, SMS-EMOA), or (MOEA/D,
// once each weight has its member) the design replaces up to two of its subproblem's neighbours
// it beats in their Tchebycheff distance from the box's ideal (the origin), weighted by theirs.
void Asynchronous::survive(Member m, std::size_t subproblem) {
  if (space_.search.algorithm != Algorithm::moead || members_.size() < population_) {
    members_.push_back(std::move(m));
    if (members_.size() <= population_) return;
    std::vector<std::vector<double>> f;
    for (const auto& member : members_) f.push_back(member.f);
    members_.erase(members_.begin() + static_cast<long>(leaving(f, space_.search.algorithm)));
    return;
  }
  std::vector<std::vector<double>> f;
  for (const auto& member : members_) f.push_back(member.f);
  for (const auto j : moead_replaced(f, neighbours_.at(subproblem), weights_, m.f)) members_[j] = m;
}

// MOEA/D's weights (pagmo2's low-discrepancy ones, a member each) and their neighbourhoods.
void Asynchronous::decompose() {
  if (space_.search.algorithm != Algorithm::moead) return;
  pagmo::detail::random_engine_type engine(static_cast<unsigned>(seed_));
  weights_ = pagmo::decomposition_weights(space_.objectives.size(), population_, "low discrepancy", engine);
  for (std::size_t i = 0; i < weights_.size(); ++i) {
    std::vector<std::size_t> order(weights_.size());
    std::iota(order.begin(), order.end(), 0);
    const auto distance = [&](std::size_t j) {
      double d = 0.0;
      for (std::size_t k = 0; k < weights_[i].size(); ++k) d += std::pow(weights_[i][k] - weights_[j][k], 2);
      return d;
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return distance(a) < distance(b); });
    order.resize(std::min(kMoeadNeighbours, order.size()));
    neighbours_.push_back(std::move(order));
  }
}

// A finished design joins the archive and the population; every `population` designs close a
// generation.
void Asynchronous::join(const Evaluation& e, bool replaying, std::size_t subproblem) {
  const auto x = space_.encode(e.spec);
  if (!x) throw std::logic_error(fmt::format("design {} is not one of the space's", e.description));
  if (!replaying) store_.put_join(run_, static_cast<long>(archive_.size()), e.digest);
  archive_.push_back(e);
  known_.insert(e.digest);
  if (join_front(space_, front_, e)) {  // the front, kept as designs join (a front of the whole archive grew as its square)
    auto d = dominator_over(space_, front_);
    const std::lock_guard<std::mutex> lock(front_m_);
    front_dominator_ = std::move(d);
  }
  auto point = fitness(space_, e, &*norm_);
  if (space_.search.screening > 1) screening_.add(*x, point, e.feasible);
  survive({*x, e.digest, std::move(point)}, subproblem);
  if (archive_.size() % population_ == 0) {
    const int index = static_cast<int>(archive_.size() / population_) - 1;
    hypervolumes_.push_back(normalised_hypervolume(space_, *norm_, front_));
    if (!replaying || index > last_generation_) record_generation(index);
  }
}

void Asynchronous::record_generation(int index) {
  Generation g;
  g.run = run_;
  g.index = index;
  for (const auto& m : members_) {
    g.population.push_back(m.x);
    g.digests.push_back(m.digest);
  }
  g.hypervolume = hypervolumes_.back();
  g.evaluations = static_cast<int>(population_);
  store_.put_generation(g);
  last_generation_ = index;
  result_.last_generation = index;
  if (options_.on_generation) options_.on_generation(g);
  const int k = space_.search.stagnation;
  if (k > 0 && index >= k) {
    const double now = hypervolumes_[static_cast<std::size_t>(index)], then = hypervolumes_[static_cast<std::size_t>(index - k)];
    if (now - then <= space_.search.stagnation_tolerance * now && ended_.empty()) ended_ = "stagnation";
  }
}

std::vector<double> Asynchronous::uniform(std::mt19937& rng) const {
  std::vector<double> x(space_.genes());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = std::uniform_int_distribution<int>(static_cast<int>(bounds_.first[i]), static_cast<int>(bounds_.second[i]))(rng);
  }
  return x;
}

// Two parents (each, with probability front_parents, one of the search's front; else by the
// algorithm's rule: binary tournaments on (rank, crowding) for NSGA-II), pagmo2's crossover of
// them (two-point: every gene is a whole number), then mutate() (or, at step_mutation = 0,
// pagmo2's mutation, which draws a mutated whole-number gene uniformly from its range).
std::vector<double> Asynchronous::bred(std::mt19937& rng, std::size_t subproblem) const {
  std::vector<pagmo::vector_double> f;
  for (const auto& m : members_) f.push_back(m.f);
  const auto [fronts, dom_list, dom_count, rank] = pagmo::fast_non_dominated_sorting(f);
  std::vector<double> crowding(members_.size(), std::numeric_limits<double>::infinity());
  for (const auto& front : fronts) {
    if (front.size() < 3) continue;
    std::vector<pagmo::vector_double> points;
    for (const auto i : front) points.push_back(f[i]);
    const auto d = pagmo::crowding_distance(points);
    for (std::size_t j = 0; j < front.size(); ++j) crowding[front[j]] = d[j];
  }
  std::uniform_int_distribution<std::size_t> any(0, members_.size() - 1);
  const auto tournament = [&] {
    const auto a = any(rng), b = any(rng);
    if (rank[a] != rank[b]) return rank[a] < rank[b] ? a : b;
    return crowding[a] >= crowding[b] ? a : b;
  };
  // NSGA-III and SMS-EMOA pick their parents at random; MOEA/D from the subproblem's
  // neighbourhood (with probability 0.9, else from the whole population).
  const auto algorithm = space_.search.algorithm;
  const bool moead = algorithm == Algorithm::moead && members_.size() == population_;
  const auto& near = neighbours_.empty() ? std::vector<std::size_t>{} : neighbours_.at(subproblem);
  const bool local = moead && std::uniform_real_distribution<double>(0.0, 1.0)(rng) < kMoeadLocalMating;
  std::uniform_int_distribution<std::size_t> in_near(0, near.empty() ? 0 : near.size() - 1);
  const auto pick = [&] {
    if (local) return near[in_near(rng)];
    return algorithm == Algorithm::nsga2 ? tournament() : any(rng);
  };
  const auto& o = space_.search;
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  const auto parent = [&]() -> std::vector<double> {
    // (no draw at front_parents = 0: the search breeds as it did before the setting existed)
    if (front_.empty() || o.front_parents <= 0.0 || !(chance(rng) < o.front_parents)) return members_[pick()].x;
    return *space_.encode(front_[std::uniform_int_distribution<std::size_t>(0, front_.size() - 1)(rng)].spec);
  };
  const auto x1 = parent(), x2 = parent();
  auto child = pagmo::sbx_crossover(x1, x2, bounds_, space_.genes(), o.crossover_probability, o.crossover_eta, rng).first;
  const double pm = o.mutation_probability.value_or(1.0 / static_cast<double>(space_.genes()));
  if (o.step_mutation > 0.0) {
    mutate(space_, bounds_, child, pm, rng);
  } else {  // as the search bred before step_mutation existed
    pagmo::polynomial_mutation(child, bounds_, space_.genes(), pm, o.mutation_eta, rng);
  }
  return child;
}

// Whether a design breaks a constraint known before it runs; the reasons are counted, so that an
// exhausted space says why its draws were refused.
bool Asynchronous::rejected(const Geometry& g) {
  const auto& violations = g.violations;
  for (const auto& v : violations) ++rejections_[v.substr(0, std::min<std::size_t>(v.find('\n'), 300))];
  return !violations.empty();
}

// The next design to run: bred once the population holds two, drawn uniformly before (the
// initial population) and after kBredDraws clones; nullopt when kDrawsPerDesign draws found no new
// design within the constraints.
std::optional<Job> Asynchronous::draw() {
  // The designs [search] start names come first, those not known yet.
  for (const auto& genes : space_.search.start) {
    const auto x = space_.canonical_genes(genes);
    auto spec = space_.decode(x);
    auto digest = spec_digest(spec);
    if (!known_.insert(digest).second || rejected(spec)) continue;
    ++drawn_;
    return Job{x, std::move(spec), std::nullopt, standing(digest), static_cast<std::size_t>(drawn_ - 1) % population_};
  }
  auto rng = stream(seed_, drawn_);
  const auto subproblem = static_cast<std::size_t>(drawn_) % population_;
  const bool initial = static_cast<std::size_t>(drawn_) < population_ || members_.size() < 2;
  if (!initial && space_.search.screening > 1) {
    if (auto job = screened(rng, subproblem)) return job;
  }
  for (int attempt = 0; attempt < kDrawsPerDesign; ++attempt) {
    const auto x = space_.canonical_genes(!initial && attempt < kBredDraws ? bred(rng, subproblem) : uniform(rng));
    auto spec = space_.decode(x);
    auto digest = spec_digest(spec);
    if (!known_.insert(digest).second) continue;
    if (rejected(spec)) continue;  // rejected before it runs; known from now on
    ++drawn_;
    return Job{x, std::move(spec), std::nullopt, standing(digest), subproblem};
  }
  return std::nullopt;
}

// [search] screening: of up to `screening` new designs within the known constraints, half of them
// (rounded up) bred and the rest drawn uniformly from the space (where the population has not
// been, the estimate judges too), the one whose estimate (Screening) would gain the front the most
// (the first drawn of equals); those not chosen are not known, and may be drawn again. None found:
// nullopt, and draw() goes on as without.
std::optional<Job> Asynchronous::screened(std::mt19937& rng, std::size_t subproblem) {
  const auto wanted = static_cast<std::size_t>(space_.search.screening);
  struct Candidate {
    std::vector<double> x;
    model::StackSpec spec;
    std::vector<std::optional<double>> known;  // its axes known before it runs
  };
  std::vector<Candidate> candidates;
  std::set<std::string> seen;
  const std::size_t bred_wanted = wanted - wanted / 2;
  for (int attempt = 0; attempt < kBredDraws && candidates.size() < wanted; ++attempt) {
    const bool breed = candidates.size() < bred_wanted && attempt < kBredDraws / 2;  // then uniform ones
    const auto x = space_.canonical_genes(breed ? bred(rng, subproblem) : uniform(rng));
    auto spec = space_.decode(x);
    const auto digest = spec_digest(spec);
    if (known_.count(digest) != 0 || !seen.insert(digest).second) continue;
    const auto geometry = measure(space_, spec);
    if (rejected(geometry)) {
      known_.insert(digest);
      continue;
    }
    candidates.push_back({x, std::move(spec), known_axes(space_, *norm_, geometry)});
  }
  if (candidates.empty()) return std::nullopt;
  std::vector<std::vector<double>> front;
  for (const auto& e : front_) front.push_back(fitness(space_, e, &*norm_));
  const ScreeningGain gain(std::move(front));
  std::vector<double> gains;
  for (const auto& c : candidates) gains.push_back(gain(screening_.estimate(c.x, c.known)));
  auto& chosen = candidates[screened_choice(gains)];
  auto digest = spec_digest(chosen.spec);
  known_.insert(digest);
  ++drawn_;
  return Job{std::move(chosen.x), std::move(chosen.spec), std::nullopt, standing(digest), subproblem};
}

// The designs the run joins before it ends: its generations', or its budget.
long Asynchronous::limit() const {
  const long target = static_cast<long>(population_) * (space_.search.generations + 1);
  return std::min(target, space_.search.max_designs.value_or(target));
}

// A design starts while fewer than the limit have finished (the probes that may begin the search
// counting as joined before the box) and the designs in flight would not take the search past it
// (`searching`: those running, probes aside): a budget of N designs runs N, never more.
bool Asynchronous::may_start(int searching) {
  const long target = static_cast<long>(population_) * (space_.search.generations + 1);
  if (ended_.empty() && finished() >= limit()) ended_ = finished() >= target ? "generations" : "max_designs";
  if (ended_.empty() && Clock::now() >= deadline_) ended_ = "time limit";
  return ended_.empty() && finished() + searching < limit();
}

// The probes the store lacks start first (the search's first designs fill the other threads).
void Asynchronous::start_probes(Pool& pool) {
  if (norm_) return;
  std::set<std::string> warm;
  for (const auto& p : probe_designs(space_)) {
    if (space_.encode(p.spec)) warm.insert(spec_digest(p.spec));
    if (store_.find(spec_digest(p.spec))) continue;
    pool.start(Job{{}, p.spec, p, std::nullopt, 0});
    ++probes_running_;
  }
  warm_expected_ = static_cast<long>(warm.size());
  if (probes_running_ == 0) probe_done(Finished{});
}

// A probe ended: stored; after the last, the box is fixed, the probes that are designs of the
// space join first, then the designs that ended meanwhile, in the order they ended.
void Asynchronous::probe_done(const Finished& f) {
  if (f.evaluation) {
    store_probe(store_, *f.job.probe, *f.evaluation);
    ++result_.runs;
    ++result_.probes;
    --probes_running_;
  }
  if (probes_running_ > 0) return;
  fix_box(space_, store_);
  norm_ = stored_normalisation(store_);
  for (const auto& e : warm_designs(space_, store_)) join(e, false);
  for (const auto& [e, subproblem] : std::exchange(held_, {})) joined(e, false, subproblem);
}

// A design that ended (stored: run before, by another seed's run) joins, or waits for the box.
void Asynchronous::joined(const Evaluation& e, bool stored, std::size_t subproblem) {
  if (!norm_) {
    held_.push_back({e, subproblem});
    return;
  }
  if (!stored) store_.put(e);
  join(e, false, subproblem);
  if (options_.on_progress) {
    const auto in = archive_.size() % population_;
    options_.on_progress(last_generation_ + 1, static_cast<int>(in == 0 ? population_ : in), static_cast<int>(population_));
  }
}

void Asynchronous::take(std::vector<Finished> done, std::exception_ptr& error) {
  for (auto& f : done) {
    if (f.error) {
      if (!error) error = f.error;
      if (!f.job.probe) known_.erase(spec_digest(f.job.spec));  // not stored: a resume runs it
      continue;
    }
    if (f.job.probe) {
      probe_done(f);
      continue;
    }
    if (finished() >= limit()) continue;  // ended beside the last one the run needed: not joined, not stored
    f.evaluation->searched = true;
    ++result_.runs;
    joined(*f.evaluation, false, f.job.subproblem);
  }
}

// Starts designs while threads are free and the search goes on, and takes back those that end,
// until it has ended and nothing it needs still runs.
void Asynchronous::search(Pool& pool, int jobs, std::exception_ptr& error) {
  start_probes(pool);
  for (;;) {
    if (os::interrupt_signal() != 0) {
      take(pool.finished(std::chrono::milliseconds(0)), error);
      throw refsim::InSituStopped("stopped by a signal");  // the pool abandons what runs
    }
    int running = pool.running();
    while (!error && running < jobs && may_start(running - probes_running_)) {
      auto job = draw();
      if (!job) {
        ended_ = "exhausted";
        break;
      }
      if (job->ready) {
        joined(*job->ready, true, job->subproblem);
        continue;
      }
      pool.start(std::move(*job));
      ++running;
    }
    // Ended but for a space with nothing new (its running designs are new ones, and finish):
    // what still runs is abandoned, once the probes have fixed the box.
    if (running == 0 || error || (!ended_.empty() && ended_ != "exhausted" && probes_running_ == 0)) return;
    take(pool.finished(std::chrono::milliseconds(100)), error);
  }
}

SearchResult Asynchronous::run() {
  decompose();
  replay();
  if (options_.time_limit > 0.0) {
    deadline_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.time_limit));
  }
  const int jobs = std::max(1, options_.jobs);
  std::exception_ptr error;
  Pool pool(space_, options_.runner, [this](const std::vector<double>& v) { return dominated(v); });
  // The caller's thread searches; `jobs` more run the designs.
  os::Workers(jobs + 1).run([&](int t) {
    if (t > 0) return pool.work();
    struct Closing {
      Pool& pool;
      ~Closing() { pool.close(); }  // however the search ends, the threads return
    } closing{pool};
    search(pool, jobs, error);
  });
  if (error) std::rethrow_exception(error);
  result_.ended = ended_.empty() ? "generations" : ended_;
  if (ended_ == "exhausted" && !rejections_.empty()) {
    const auto most = std::max_element(rejections_.begin(), rejections_.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    long all = 0;
    for (const auto& [why, n] : rejections_) all += n;
    result_.exhausted_because = fmt::format("{} of the {} refusals: {}", most->second, all, most->first);
  }
  return result_;
}

}  // namespace

std::vector<std::size_t> moead_replaced(const std::vector<std::vector<double>>& members, const std::vector<std::size_t>& neighbours,
                                        const std::vector<std::vector<double>>& weights, const std::vector<double>& f) {
  const pagmo::vector_double ideal(f.size(), 0.0);
  std::vector<std::size_t> replaced;
  for (const auto j : neighbours) {
    if (replaced.size() >= static_cast<std::size_t>(kMoeadReplacements)) break;
    const auto g = [&](const std::vector<double>& x) { return pagmo::decompose_objectives(x, weights[j], ideal, "tchebycheff")[0]; };
    if (g(f) <= g(members[j])) replaced.push_back(j);
  }
  return replaced;
}

SearchResult run_asynchronous(const Space& space, Store& store, const SearchOptions& options, int run) {
  return Asynchronous(space, store, options, run).run();
}

}  // namespace granstack::design
