#include "dem/world/tool.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dem {

namespace {

// Every wall and clamped particle of the tool follows `m`.
void set_tool_motion(World& w, const Tool& t, const Motion& m) {
    for (uint32_t f = t.facet0; f < t.facet1; ++f) w.facets[f].motion = m;
    if (t.motion >= 0) w.motions[std::size_t(t.motion)] = m;
}

const Motion* tool_motion(const World& w, const Tool& t) {
    if (t.facet1 > t.facet0) return &w.facets[t.facet0].motion;
    if (t.motion >= 0) return &w.motions[std::size_t(t.motion)];
    return nullptr;
}

DisplacementSample knot(double time, double z) { return {time, Vec3{0.0, 0.0, z}}; }

// Seconds of one triangle cycle of segment g: out by the amplitude and back.
double cycle_period(const ToolSegment& g) { return 2.0 * std::abs(g.amplitude) / g.speed; }

}  // namespace

void add_tool_facets(World& w, Tool& t, const std::vector<Facet>& facets) {
    if (t.facet1 > t.facet0 && t.facet1 != w.facets.size())
        throw std::invalid_argument("add_tool_facets: tool '" + t.name + "' has facets that are not the last ones");
    if (t.facet1 == t.facet0) t.facet0 = t.facet1 = uint32_t(w.facets.size());
    for (const Facet& f : facets) w.add_facet(f);
    t.facet1 = uint32_t(w.facets.size());
}

void clamp_to_tool(World& w, Tool& t, const std::vector<uint32_t>& particles) {
    if (particles.empty()) return;
    if (t.motion < 0) {
        const Motion* m = tool_motion(w, t);
        t.motion = int32_t(w.add_motion(m ? *m : Motion{}));
    }
    for (uint32_t i : particles) {
        w.set_prescribed(i, uint32_t(t.motion));
        t.clamped.push_back(i);
    }
}

double tool_displacement(const World& w, const Tool& t, double time) {
    const Motion* m = tool_motion(w, t);
    return m ? m->displacement(time).z : 0.0;
}

Vec3 tool_force(const World& w, const Tool& t) {
    Vec3 f;
    // Before the first compute_forces() there are no reactions yet.
    if (w.wall_state().force.size() == w.wall_count())
        for (uint32_t k = t.facet0; k < t.facet1; ++k) f += w.wall_force(w.planes.size() + k);
    for (uint32_t i : t.clamped) f += w.particles.force[i];
    return f;
}

bool drive_tool(World& w, const Tool& t, ToolState& s, int32_t stage) {
    const double dt = w.params.dt, now = w.time;
    while (s.segment < int32_t(t.program.size())) {
        const ToolSegment& g = t.program[std::size_t(s.segment)];
        if (g.stage < stage) {  // an earlier stage's segment left unfinished
            ++s.segment;
            s.started = 0;
            continue;
        }
        if (g.stage > stage) break;
        // The knot one step back keeps the wall velocity of the coming step (the mean over
        // [now - dt, now]) what the old motion gave.
        const double d_back = tool_displacement(w, t, now - dt);
        if (!s.started) {
            s.started = 1;
            s.t0 = now;
            s.d0 = tool_displacement(w, t, now);
            Motion m;
            m.history = {knot(now - dt, d_back), knot(now, s.d0)};
            if (g.kind == SegmentKind::Move && g.to != s.d0)
                m.history.push_back(knot(now + std::abs(g.to - s.d0) / g.speed, g.to));
            if (g.kind == SegmentKind::Cycle) {
                const double half = 0.5 * cycle_period(g);
                for (int k = 0; k < g.cycles; ++k) {
                    m.history.push_back(knot(now + (2 * k + 1) * half, s.d0 + g.amplitude));
                    m.history.push_back(knot(now + (2 * k + 2) * half, s.d0));
                }
            }
            set_tool_motion(w, t, m);
        }
        bool done = false;
        switch (g.kind) {
        case SegmentKind::Move: done = now >= s.t0 + std::abs(g.to - s.d0) / g.speed - 0.5 * dt; break;
        case SegmentKind::Hold: done = now >= s.t0 + g.duration - 0.5 * dt; break;
        case SegmentKind::Cycle: done = now >= s.t0 + g.cycles * cycle_period(g) - 0.5 * dt; break;
        case SegmentKind::ForceHold: {
            done = now >= s.t0 + g.duration - 0.5 * dt;
            const double d = tool_displacement(w, t, now);
            const double e = std::clamp((g.force - tool_force(w, t).z) / std::abs(g.force), -1.0, 1.0);
            Motion m;
            m.history = {knot(now - dt, d_back), knot(now, d)};
            if (!done) m.history.push_back(knot(now + dt, d - (g.force > 0 ? 1.0 : -1.0) * g.speed * e * dt));
            set_tool_motion(w, t, m);
            break;
        }
        case SegmentKind::Force: {
            // The reaction of the step before decides this step's move: a one-step lag, as a
            // testing machine's controller has one sample's.
            const double d = tool_displacement(w, t, now);
            const double f = tool_force(w, t).z;
            done = (g.force > 0 ? f >= g.force : f <= g.force) || std::abs(d - s.d0) >= g.max_travel;
            Motion m;
            m.history = {knot(now - dt, d_back), knot(now, d)};
            if (!done) m.history.push_back(knot(now + dt, d + (g.force > 0 ? -1.0 : 1.0) * g.speed * dt));
            set_tool_motion(w, t, m);
            break;
        }
        }
        if (!done) return false;
        ++s.segment;
        s.started = 0;
    }
    return true;
}

double program_duration(const Tool& t, int32_t stage, double d) {
    double sum = 0.0;
    for (const ToolSegment& g : t.program) {
        if (g.stage != stage) continue;
        switch (g.kind) {
        case SegmentKind::Move:
            sum += std::abs(g.to - d) / g.speed;
            d = g.to;
            break;
        case SegmentKind::Hold:
        case SegmentKind::ForceHold: sum += g.duration; break;
        case SegmentKind::Cycle: sum += g.cycles * cycle_period(g); break;
        case SegmentKind::Force:
            sum += g.max_travel / g.speed;
            d += (g.force > 0 ? -1.0 : 1.0) * g.max_travel;
            break;
        }
    }
    return sum;
}

}  // namespace dem
