// The thin C++ side of the `ompl:<name>` planners (cargo feature `ompl`): builds OMPL's
// control-based SimpleSetup for one magbench problem and runs one of OMPL's planners on it.
//
// There is no model here. OMPL's StatePropagator, StateValidityChecker and goal call back into
// magbench (planners/src/ompl/ffi.rs) over the C ABI below:
// - propagate: one propagation step (the control period) through magbench's PlanningModel,
//   checked continuously by magbench's edge check; an invalid step writes NaN into the result,
//   so the validity checker rejects it and OMPL's propagateWhileValid stops before it;
// - valid: magbench's ValidityChecker::is_valid on a finite state;
// - goal: the largest agent distance from its goal centre, and whether the goal holds;
// - tick: every evaluation of the termination condition (once per planner iteration); magbench
//   counts iterations, records progress and says when a limit is reached;
// - solution: each improved solution of SST (its controls and steps), for the progress trace.
// Every RNG that OMPL's planner and its samplers own is reseeded from the problem's seed, so a
// run is reproducible whatever else the process (or another thread) does with OMPL.

#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SimpleSetup.h>
#include <ompl/control/planners/est/EST.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/pdst/PDST.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace ob = ompl::base;
namespace oc = ompl::control;

extern "C" {

/// magbench's side: the model, the checks, the goal and the limits.
struct mb_callbacks {
    void *ctx;
    int (*propagate)(void *ctx, const double *state, const double *control, double duration,
                     double *result);
    int (*valid)(void *ctx, const double *state);
    double (*goal_distance)(void *ctx, const double *state);
    int (*goal_satisfied)(void *ctx, const double *state);
    int (*tick)(void *ctx);
    void (*solution)(void *ctx, size_t edges, const double *controls, const unsigned *steps);
};

/// One planning problem.
struct mb_problem {
    const char *planner;  // rrt, sst, kpiece, est, pdst
    size_t agents;
    double width, height;        // the world's rectangle (BL)
    const double *start;         // 2 * agents
    const double *goal_centres;  // 2 * agents
    double goal_tolerance;       // BL
    double gradient_limit;       // T/m
    double step;                 // the control period (s): OMPL's propagation step
    unsigned min_steps, max_steps;
    uint64_t seed;
    int stop_on_solution;        // SST: stop at the first solution
    size_t n_params;
    const char *const *param_names;
    const char *const *param_values;
    size_t control_dims;         // 3: (θ_B, g_x, g_y), planar; 4: (θ_B, g_x, g_y, α)
    double alpha_max;            // rad: α ∈ [0, alpha_max] when control_dims = 4
};

/// What a run found. `controls` (control_dims per edge), `steps` and `states` (2·agents per waypoint)
/// are owned by the shim; free with mb_ompl_free.
struct mb_result {
    int status;  // 0: no path, 1: approximate, 2: exact
    uint64_t vertices;       // PlannerData vertices (for SST: motions in its tree)
    uint64_t witnesses;      // SST: witnesses
    uint64_t dominated;      // SST: leaves that are no witness's representative
    size_t edges;
    double *controls;
    unsigned *steps;
    double *states;
    char error[512];
};
}

namespace {

/// The control space's dimension: 3 (θ_B, g_x, g_y; planar, α = 0) or 4 (… , α).
size_t controlDims(const oc::ControlSpace *space) { return space->getDimension(); }

/// A seed for the `k`-th RNG of a run (splitmix64 of the run's seed and k).
std::uint_fast32_t derive(uint64_t seed, uint64_t k) {
    uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (k + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<std::uint_fast32_t>((z ^ (z >> 31)) & 0xFFFFFFFFULL);
}

/// Hands out the seeds of one run's RNGs in allocation order (deterministic: one thread).
struct Seeds {
    uint64_t seed;
    uint64_t next = 0;
    std::uint_fast32_t take() { return derive(seed, next++); }
};

class SeededStateSampler : public ob::RealVectorStateSampler {
public:
    SeededStateSampler(const ob::StateSpace *space, std::uint_fast32_t seed)
        : ob::RealVectorStateSampler(space) {
        rng_.setLocalSeed(seed);
    }
};

class SeededControlSampler : public oc::RealVectorControlUniformSampler {
public:
    SeededControlSampler(const oc::ControlSpace *space, std::uint_fast32_t seed)
        : oc::RealVectorControlUniformSampler(space) {
        rng_.setLocalSeed(seed);
    }
};

/// A planner whose own RNG is reseeded.
template <class P>
class Seeded : public P {
public:
    Seeded(const oc::SpaceInformationPtr &si, std::uint_fast32_t seed) : P(si) {
        this->rng_.setLocalSeed(seed);
    }
};

/// SST, reseeded, with read access to its counts and its current solution.
class SeededSst : public Seeded<oc::SST> {
public:
    using Seeded<oc::SST>::Seeded;
    uint64_t motions() const { return nn_ ? nn_->size() : 0; }
    uint64_t witnessCount() const { return witnesses_ ? witnesses_->size() : 0; }
    /// Leaves of the tree that represent no witness: the dominated nodes the paper prunes.
    uint64_t dominatedLeaves() const {
        if (!nn_ || !witnesses_) return 0;
        std::vector<Motion *> ws, ms;
        witnesses_->list(ws);
        nn_->list(ms);
        std::vector<const Motion *> reps;
        for (auto *w : ws) reps.push_back(static_cast<Witness *>(w)->rep_);
        std::sort(reps.begin(), reps.end());
        uint64_t n = 0;
        for (auto *m : ms)
            if (m->numChildren_ == 0 && !std::binary_search(reps.begin(), reps.end(), m)) ++n;
        return n;
    }
    /// The cost of the current solution in OMPL's objective (infinite before the first).
    double solutionCost() const { return prevSolutionCost_.value(); }
    /// The current solution's controls and steps, from the start.
    void solution(std::vector<double> &controls, std::vector<unsigned> &steps) const {
        controls.clear();
        steps.clear();
        for (size_t i = prevSolutionControls_.size(); i-- > 0;) {
            const double *u =
                prevSolutionControls_[i]->as<oc::RealVectorControlSpace::ControlType>()->values;
            controls.insert(controls.end(), u, u + controlDims(siC_->getControlSpace().get()));
            steps.push_back(prevSolutionSteps_[i]);
        }
    }
};

double *values(ob::State *s) { return s->as<ob::RealVectorStateSpace::StateType>()->values; }
const double *values(const ob::State *s) {
    return s->as<ob::RealVectorStateSpace::StateType>()->values;
}

/// One propagation step through magbench; NaN marks a step its edge check refused.
class Propagator : public oc::StatePropagator {
public:
    Propagator(const oc::SpaceInformationPtr &si, const mb_callbacks *cb, size_t dims)
        : oc::StatePropagator(si), cb_(cb), dims_(dims) {}
    void propagate(const ob::State *state, const oc::Control *control, double duration,
                   ob::State *result) const override {
        const double *u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
        double *out = values(result);
        if (!cb_->propagate(cb_->ctx, values(state), u, duration, out))
            for (size_t i = 0; i < dims_; ++i) out[i] = std::numeric_limits<double>::quiet_NaN();
    }

private:
    const mb_callbacks *cb_;
    size_t dims_;
};

/// magbench's state check; a NaN state (a refused step) is invalid.
class Checker : public ob::StateValidityChecker {
public:
    Checker(const ob::SpaceInformationPtr &si, const mb_callbacks *cb, size_t dims)
        : ob::StateValidityChecker(si), cb_(cb), dims_(dims) {}
    bool isValid(const ob::State *state) const override {
        const double *x = values(state);
        for (size_t i = 0; i < dims_; ++i)
            if (!std::isfinite(x[i])) return false;
        return cb_->valid(cb_->ctx, x) != 0;
    }

private:
    const mb_callbacks *cb_;
    size_t dims_;
};

/// The goal: each agent within the tolerance of its centre; goal samples are uniform in the
/// agents' goal disks.
class Goal : public ob::GoalSampleableRegion {
public:
    Goal(const ob::SpaceInformationPtr &si, const mb_callbacks *cb, const mb_problem &p,
         std::uint_fast32_t seed)
        : ob::GoalSampleableRegion(si), cb_(cb),
          centres_(p.goal_centres, p.goal_centres + 2 * p.agents), radius_(p.goal_tolerance) {
        setThreshold(p.goal_tolerance);
        rng_.setLocalSeed(seed);
    }
    double distanceGoal(const ob::State *st) const override {
        return cb_->goal_distance(cb_->ctx, values(st));
    }
    bool isSatisfied(const ob::State *st) const override {
        return cb_->goal_satisfied(cb_->ctx, values(st)) != 0;
    }
    bool isSatisfied(const ob::State *st, double *distance) const override {
        if (distance) *distance = distanceGoal(st);
        return isSatisfied(st);
    }
    void sampleGoal(ob::State *st) const override {
        double *x = values(st);
        for (size_t i = 0; i < centres_.size() / 2; ++i) {
            double r = radius_ * std::sqrt(rng_.uniform01());
            double a = rng_.uniformReal(-M_PI, M_PI);
            x[2 * i] = centres_[2 * i] + r * std::cos(a);
            x[2 * i + 1] = centres_[2 * i + 1] + r * std::sin(a);
        }
    }
    unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned>::max(); }

private:
    const mb_callbacks *cb_;
    std::vector<double> centres_;
    double radius_;
    mutable ompl::RNG rng_;
};

/// The agents' positions themselves (2N dimensions, cells of 1/20 of the world's sides): the
/// grid of KPIECE1 and EST and PDST's subdivision. A projection to the centroid alone cannot
/// tell the team's shapes apart, and these problems are about shape.
class Projection : public ob::ProjectionEvaluator {
public:
    Projection(const ob::StateSpace *space, size_t agents, double width, double height)
        : ob::ProjectionEvaluator(space), dims_(2 * agents), width_(width), height_(height) {
        ob::RealVectorBounds b(dims_);
        for (size_t i = 0; i < dims_; ++i) {
            b.setLow(i, 0.0);
            b.setHigh(i, i % 2 == 0 ? width : height);
        }
        setBounds(b);
    }
    unsigned int getDimension() const override { return dims_; }
    void defaultCellSizes() override {
        cellSizes_.resize(dims_);
        for (size_t i = 0; i < dims_; ++i) cellSizes_[i] = (i % 2 == 0 ? width_ : height_) / 20.0;
    }
    void project(const ob::State *state, Eigen::Ref<Eigen::VectorXd> projection) const override {
        const double *x = values(state);
        for (size_t i = 0; i < dims_; ++i) projection[i] = x[i];
    }

private:
    size_t dims_;
    double width_, height_;
};

/// The agents' positions; its default projection is [`Projection`] (RealVectorStateSpace's own
/// default for more than two dimensions is a random linear projection from an unseeded RNG,
/// registered again at every setup).
class Positions : public ob::RealVectorStateSpace {
public:
    Positions(size_t agents, double width, double height)
        : ob::RealVectorStateSpace(2 * agents), agents_(agents), width_(width), height_(height) {
        ob::RealVectorBounds b(2 * agents);
        for (size_t i = 0; i < agents; ++i) {
            b.setLow(2 * i, 0.0);
            b.setHigh(2 * i, width);
            b.setLow(2 * i + 1, 0.0);
            b.setHigh(2 * i + 1, height);
        }
        setBounds(b);
    }
    void registerProjections() override {
        registerDefaultProjection(std::make_shared<Projection>(this, agents_, width_, height_));
    }

private:
    size_t agents_;
    double width_, height_;
};

void fail(mb_result *r, const std::string &why) {
    std::strncpy(r->error, why.c_str(), sizeof r->error - 1);
    r->error[sizeof r->error - 1] = 0;
}

int solve(const mb_problem &p, const mb_callbacks *cb, mb_result *r) {
    static std::once_flag quiet;
    std::call_once(quiet, [] { ompl::msg::noOutputHandler(); });

    const size_t dims = 2 * p.agents;
    Seeds seeds{p.seed};
    auto space = std::make_shared<Positions>(p.agents, p.width, p.height);
    space->setStateSamplerAllocator([&seeds](const ob::StateSpace *s) -> ob::StateSamplerPtr {
        return std::make_shared<SeededStateSampler>(s, seeds.take());
    });

    if (p.control_dims != 3 && p.control_dims != 4) {
        fail(r, "control_dims must be 3 or 4");
        return 1;
    }
    const size_t cdims = p.control_dims;
    auto cspace = std::make_shared<oc::RealVectorControlSpace>(space, cdims);
    ob::RealVectorBounds cbounds(cdims);
    cbounds.setLow(0, -M_PI);
    cbounds.setHigh(0, M_PI);
    for (size_t i = 1; i < 3; ++i) {
        cbounds.setLow(i, -p.gradient_limit);
        cbounds.setHigh(i, p.gradient_limit);
    }
    if (cdims == 4) {  // the elevation: α and −α move the agents alike in the plane
        cbounds.setLow(3, 0.0);
        cbounds.setHigh(3, p.alpha_max);
    }
    cspace->setBounds(cbounds);
    cspace->setControlSamplerAllocator([&seeds](const oc::ControlSpace *s) -> oc::ControlSamplerPtr {
        return std::make_shared<SeededControlSampler>(s, seeds.take());
    });

    oc::SimpleSetup ss(cspace);
    auto si = ss.getSpaceInformation();
    ss.setStatePropagator(std::make_shared<Propagator>(si, cb, dims));
    ss.setStateValidityChecker(std::make_shared<Checker>(si, cb, dims));
    si->setPropagationStepSize(p.step);
    si->setMinMaxControlDuration(p.min_steps, p.max_steps);

    ob::ScopedState<ob::RealVectorStateSpace> start(space);
    for (size_t i = 0; i < dims; ++i) start[i] = p.start[i];
    ss.setStartState(start);
    ss.setGoal(std::make_shared<Goal>(si, cb, p, seeds.take()));

    const std::string name = p.planner;
    std::shared_ptr<SeededSst> sst;
    ob::PlannerPtr planner;
    if (name == "rrt") planner = std::make_shared<Seeded<oc::RRT>>(si, seeds.take());
    else if (name == "kpiece") planner = std::make_shared<Seeded<oc::KPIECE1>>(si, seeds.take());
    else if (name == "est") planner = std::make_shared<Seeded<oc::EST>>(si, seeds.take());
    else if (name == "pdst") planner = std::make_shared<Seeded<oc::PDST>>(si, seeds.take());
    else if (name == "sst") planner = sst = std::make_shared<SeededSst>(si, seeds.take());
    else {
        fail(r, "unknown OMPL planner " + name);
        return 1;
    }
    for (size_t i = 0; i < p.n_params; ++i) {
        if (!planner->params().setParam(p.param_names[i], p.param_values[i])) {
            fail(r, std::string("OMPL's ") + planner->getName() + " refused parameter " +
                        p.param_names[i] + "=" + p.param_values[i]);
            return 1;
        }
    }
    ss.setPlanner(planner);

    // SST optimises OMPL's own cost: state-space path length.
    auto opt = std::make_shared<ob::PathLengthOptimizationObjective>(si);
    if (p.stop_on_solution) opt->setCostThreshold(ob::Cost(std::numeric_limits<double>::infinity()));
    ss.setOptimizationObjective(opt);
    ss.setup();
    // One evaluation per planner iteration. OMPL 1.5's control::SST reports no intermediate
    // solutions, so each tick also looks whether its solution improved.
    double reported = std::numeric_limits<double>::infinity();
    std::vector<double> controls;
    std::vector<unsigned> steps;
    ob::PlannerTerminationCondition ptc([&] {
        if (sst && sst->solutionCost() < reported) {
            reported = sst->solutionCost();
            sst->solution(controls, steps);
            cb->solution(cb->ctx, steps.size(), controls.data(), steps.data());
        }
        return cb->tick(cb->ctx) != 0;
    });
    ob::PlannerStatus status = ss.solve(ptc);

    if (sst) {
        r->vertices = sst->motions();
        r->witnesses = sst->witnessCount();
        r->dominated = sst->dominatedLeaves();
    } else {
        ob::PlannerData data(si);
        planner->getPlannerData(data);
        r->vertices = data.numVertices();
    }
    r->status = 0;
    if (status == ob::PlannerStatus::EXACT_SOLUTION) r->status = 2;
    else if (status == ob::PlannerStatus::APPROXIMATE_SOLUTION) r->status = 1;
    if (r->status == 0) return 0;

    const oc::PathControl &path = ss.getSolutionPath();
    const size_t edges = path.getControlCount();
    r->edges = edges;
    r->controls = static_cast<double *>(std::malloc(sizeof(double) * cdims * (edges + 1)));
    r->steps = static_cast<unsigned *>(std::malloc(sizeof(unsigned) * (edges + 1)));
    r->states = static_cast<double *>(std::malloc(sizeof(double) * dims * (edges + 1)));
    if (!r->controls || !r->steps || !r->states) {
        fail(r, "out of memory copying OMPL's path");
        return 1;
    }
    for (size_t k = 0; k < edges; ++k) {
        const double *u = path.getControl(k)->as<oc::RealVectorControlSpace::ControlType>()->values;
        std::copy(u, u + cdims, r->controls + cdims * k);
        r->steps[k] = static_cast<unsigned>(std::lround(path.getControlDuration(k) / p.step));
    }
    for (size_t k = 0; k <= edges; ++k) {
        const double *x = values(path.getState(k));
        std::copy(x, x + dims, r->states + dims * k);
    }
    return 0;
}

}  // namespace

extern "C" {

/// Runs OMPL's planner on one problem. Returns 0 on success (r->status says what was found),
/// nonzero with r->error on failure. Never throws.
int mb_ompl_solve(const mb_problem *p, const mb_callbacks *cb, mb_result *r) {
    std::memset(r, 0, sizeof *r);
    try {
        return solve(*p, cb, r);
    } catch (const std::exception &e) {
        fail(r, std::string("OMPL: ") + e.what());
    } catch (...) {
        fail(r, "OMPL: unknown exception");
    }
    return 1;
}

/// Propagates `state` under `control` for one step through OMPL's SpaceInformation (the
/// StatePropagator calling back into magbench), `repeats` times; writes the end into `result`
/// and returns the nanoseconds the loop took (the setup excluded), or -1 on failure.
int64_t mb_ompl_propagate(const mb_problem *p, const mb_callbacks *cb, const double *state,
                          const double *control, double *result, uint64_t repeats) {
    try {
        const size_t dims = 2 * p->agents;
        auto space = std::make_shared<Positions>(p->agents, p->width, p->height);
        auto cspace = std::make_shared<oc::RealVectorControlSpace>(space, p->control_dims);
        auto si = std::make_shared<oc::SpaceInformation>(space, cspace);
        si->setStatePropagator(std::make_shared<Propagator>(si, cb, dims));
        si->setStateValidityChecker(std::make_shared<Checker>(si, cb, dims));
        si->setPropagationStepSize(p->step);
        si->setMinMaxControlDuration(1, 1);
        si->setup();
        ob::State *from = si->allocState(), *to = si->allocState();
        oc::Control *u = si->allocControl();
        std::copy(state, state + dims, values(from));
        std::copy(control, control + p->control_dims,
                  u->as<oc::RealVectorControlSpace::ControlType>()->values);
        auto t0 = std::chrono::steady_clock::now();
        for (uint64_t i = 0; i < repeats; ++i) si->propagate(from, u, 1, to);
        auto t1 = std::chrono::steady_clock::now();
        std::copy(values(to), values(to) + dims, result);
        si->freeState(from);
        si->freeState(to);
        si->freeControl(u);
        return std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
    } catch (...) {
        return -1;
    }
}

/// Frees the arrays of a result.
void mb_ompl_free(mb_result *r) {
    std::free(r->controls);
    std::free(r->steps);
    std::free(r->states);
    r->controls = nullptr;
    r->steps = nullptr;
    r->states = nullptr;
}
}
