// What the report makes of its measurements: the fitted order of each method
// on each problem, the Pareto front of each problem, and our cost over
// odeint's at equal error (one particle, and per copy of the batch). Its own
// file: pure arithmetic over the samples, no timing and no output.
#include "scenes/report/report_stages.h"

#include "sim/integrators.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scenes::report {
namespace {

// --- the orders and the fronts -------------------------------------------------------------

std::vector<OrderFit> fit_orders(const Measurements& m) {
    std::vector<OrderFit> out;
    for (const Problem& p : m.problems) {
        for (const sim::IntegratorInfo& info : sim::kIntegrators) {
            const std::string name(info.name);
            out.push_back({.problem = p.name,
                           .integrator = name,
                           .fit = fit_order(samples_of(m.sweeps, p.name, name)),
                           .expected = expected_order(p, info)});
        }
    }
    return out;
}

// The Pareto front per problem: by measured time, each point beats every cheaper one.
std::vector<Sample> pareto_front(const std::string& problem, const std::vector<Sample>& samples) {
    std::vector<Sample> mine;
    for (const Sample& s : samples)
        if (s.problem == problem && std::isfinite(s.error) && s.error > 0) mine.push_back(s);
    std::sort(mine.begin(), mine.end(), [](const Sample& a, const Sample& b) { return a.seconds < b.seconds; });
    double best = std::numeric_limits<double>::infinity();
    std::vector<Sample> front;
    for (const Sample& s : mine) {
        if (s.error >= best) continue;
        best = s.error;
        front.push_back(s);
    }
    return front;
}

// --- peers: our cost at their error ---------------------------------------------------------

// Our cost at the peer's error, interpolated log-log along our sweep, over
// the peer's: the median over the peer's points in the fit band. NaN when
// the curves do not overlap.
double cost_ratio(const std::vector<Sample>& ours, const std::vector<Sample>& theirs) {
    std::vector<double> ratios;
    for (const Sample& t : theirs) {
        if (!std::isfinite(t.error) || t.error < kFitFloor || t.error > kFitCeiling) continue;
        for (std::size_t i = 0; i + 1 < ours.size(); ++i) {
            const Sample &a = ours[i], &b = ours[i + 1];  // a coarser than b: a.error > b.error
            if (!(std::isfinite(a.error) && std::isfinite(b.error)) || a.error <= 0 || b.error <= 0) continue;
            if (!(t.error <= a.error && t.error >= b.error) || a.error == b.error) continue;
            const double f = std::log(t.error / a.error) / std::log(b.error / a.error);
            const double seconds = std::exp(std::log(a.seconds) + f * (std::log(b.seconds) - std::log(a.seconds)));
            ratios.push_back(seconds / t.seconds);
            break;
        }
    }
    return ratios.empty() ? kNaN : median(ratios);
}

// The batch's cost ratio at equal error. A step of a copy costs the same
// whatever the dt, and each copy is the problem (its error at a dt is the
// single copy's), so: (our seconds per step per copy / odeint's) x (the
// steps we need / the steps they need for the same error), the second
// factor read from the single copy's sweeps as cost_ratio reads seconds (1
// for the same method: the same error at the same dt). Where the sweeps'
// errors do not overlap the ratio is at equal dt: the ballistic shot (both
// methods exact: every error is round-off), or odeint's first-order velocity
// Verlet on the damped oscillator (ours is second order: more accurate at
// the same dt, so equal dt bounds the ratio at equal error from above).
struct BatchRatio {
    double steps_ratio = kNaN;  // our steps / theirs at equal error; NaN: no overlap
    double ratio = kNaN;
    std::string basis;  // "equal error", "equal dt, both exact", "equal dt, an upper bound"
};
BatchRatio batch_ratio(const BatchResult& batch, const std::vector<Sample>& ours, const std::vector<Sample>& theirs) {
    auto steps_of = [](std::vector<Sample> sweep) {
        for (Sample& s : sweep) s.seconds = 1.0 / s.dt;  // steps per simulated second
        return sweep;
    };
    auto exact = [](const std::vector<Sample>& sweep) {
        return std::all_of(sweep.begin(), sweep.end(), [](const Sample& s) { return s.error < kFitFloor; });
    };
    BatchRatio r;
    const double per_step = batch.ours_seconds / batch.theirs_seconds;
    r.steps_ratio = cost_ratio(steps_of(ours), steps_of(theirs));
    if (std::isfinite(r.steps_ratio)) {
        r.ratio = per_step * r.steps_ratio;
        r.basis = "equal error";
    } else if (exact(ours) && exact(theirs)) {
        r.ratio = per_step;
        r.basis = "equal dt, both exact";
    } else if (batch.ours_error < batch.theirs_error) {
        r.ratio = per_step;
        r.basis = "equal dt, an upper bound";
    }
    return r;
}

PeerRow compare(const PeerSweep& peer) {
    const std::vector<Sample>& ours = peer.ours_samples;
    PeerRow row{.peer = peer.peer,
                .problem = peer.problem,
                .ours = peer.ours,
                .fit = fit_order(peer.samples),
                .ratio = cost_ratio(ours, peer.samples),
                .batch = peer.batch};
    if (peer.batch) {
        const BatchRatio b = batch_ratio(*peer.batch, ours, peer.samples);
        row.steps_ratio = b.steps_ratio;
        row.ratio_batch = b.ratio;
        row.batch_basis = b.basis;
    }
    return row;
}

// --- rigid bodies: orders and the picks for a frame budget ---------------------------------------

// Each solver-setting series' order: its headline error against h.
std::vector<RigidOrder> rigid_orders(const std::vector<RigidSample>& rigid) {
    std::vector<RigidOrder> out;
    for (std::size_t i = 0; i < rigid.size();) {
        std::vector<Sample> series;
        std::size_t j = i;
        for (; j < rigid.size() && rigid[j].problem == rigid[i].problem && rigid[j].label() == rigid[i].label(); ++j) {
            series.push_back({.problem = rigid[j].problem,
                              .integrator = rigid[j].label(),
                              .dt = rigid[j].h,
                              .error = rigid[j].error});
        }
        out.push_back({.problem = rigid[i].problem,
                       .solver = rigid[i].solver,
                       .setting = rigid[i].setting,
                       .fit = fit_order(series)});
        i = j;
    }
    return out;
}

// The most accurate point within each budget, of any solver and of ours.
std::vector<RigidPick> rigid_picks(const std::vector<RigidSample>& rigid) {
    std::vector<RigidPick> out;
    std::vector<std::string> problems;
    for (const RigidSample& s : rigid)
        if (std::find(problems.begin(), problems.end(), s.problem) == problems.end()) problems.push_back(s.problem);
    for (const std::string& problem : problems) {
        for (const double budget : kRigidBudgets) {
            RigidPick pick{.problem = problem, .budget = budget};
            for (const RigidSample& s : rigid) {
                if (s.problem != problem || s.failed || !std::isfinite(s.error) || !(s.us_per_frame <= budget))
                    continue;
                if (!pick.best || s.error < pick.best->error) pick.best = s;
                if (s.ours() && (!pick.ours || s.error < pick.ours->error)) pick.ours = s;
            }
            out.push_back(pick);
        }
    }
    return out;
}

}  // namespace

Fit fit_order(const std::vector<Sample>& samples) {
    std::vector<std::pair<double, double>> xy;
    for (const Sample& s : samples) {
        if (std::isfinite(s.error) && s.error >= kFitFloor && s.error <= kFitCeiling) {
            xy.emplace_back(std::log(s.dt), std::log(s.error));
        }
    }
    Fit f;
    f.points = static_cast<int>(xy.size());
    if (xy.size() < 3) return f;
    double mx = 0, my = 0;
    for (const auto& [x, y] : xy) mx += x, my += y;
    mx /= static_cast<double>(xy.size()), my /= static_cast<double>(xy.size());
    double sxy = 0, sxx = 0;
    for (const auto& [x, y] : xy) sxy += (x - mx) * (y - my), sxx += (x - mx) * (x - mx);
    f.slope = sxy / sxx;
    return f;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::vector<Sample> samples_of(const std::vector<Sample>& in, const std::string& problem,
                               const std::string& integrator) {
    std::vector<Sample> out;
    for (const Sample& s : in)
        if (s.problem == problem && s.integrator == integrator) out.push_back(s);
    return out;
}

Findings analyse(const Measurements& m) {
    Findings f;
    f.orders = fit_orders(m);
    // Over every point measured: the sweeps, then the frame substeps.
    std::vector<Sample> all = m.sweeps;
    all.insert(all.end(), m.frames.begin(), m.frames.end());
    for (const Problem& p : m.problems) f.fronts[p.name] = pareto_front(p.name, all);
    for (const PeerSweep& peer : m.peers) f.peers.push_back(compare(peer));
    f.rigid_orders = rigid_orders(m.rigid);
    f.rigid_picks = rigid_picks(m.rigid);
    return f;
}

const OrderFit& order_of(const Findings& f, const std::string& problem, const std::string& integrator) {
    return *std::find_if(f.orders.begin(), f.orders.end(),
                         [&](const OrderFit& o) { return o.problem == problem && o.integrator == integrator; });
}

}  // namespace scenes::report
