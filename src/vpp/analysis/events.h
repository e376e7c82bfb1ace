// Rearrangement events: which part of a cycle's dissipation happens in the bursts in which a
// jammed packing gives way, and which in the quiet creep between them (issue 60, item 3; the
// paper's open question, docs/energy.md "Events and creep").
//
// A quasi-static cycle moves the grains slowly most of the time; when a force chain buckles, a
// group of grains is released and its kinetic energy jumps by orders of magnitude for a short
// time before the friction and the damping take it. The energy ledger's channels (friction, local
// damping, dashpots) are sums over the whole cycle and cannot tell the two apart; their
// increments between consecutive records can, given a rule for "in an event".
//
// The detector (stated once, here): the cycle's baseline is the median of the kinetic energy over
// its records (robust to the bursts, which occupy a small part of the cycle); a record is in an
// event where its kinetic energy exceeds `threshold` times the baseline; the dissipation between
// two consecutive records belongs to an event when either record is in one (a burst that starts
// and ends between two records is missed: the records' spacing bounds the resolution, so a study
// of events records finely, process.samples_per_cycle). An event is a maximal run of such
// intervals. A median of 0 (nothing moves) makes every moving record an event.
#pragma once

#include <vector>

namespace vpp {

// A cycle's records, in time order: the kinetic energy and the cumulative dissipations at each
// record, the cycle's first record to the next cycle's first (or the run's last state).
struct EventSeries {
    std::vector<double> kinetic;    // [J] at each record
    std::vector<double> friction;   // [J] cumulative frictional dissipation
    std::vector<double> damping;    // [J] cumulative local-damping dissipation
    std::vector<double> viscous;    // [J] cumulative dashpot dissipation
};

struct EventSplit {
    int events = 0;                 // bursts: maximal runs of intervals in an event
    double event_fraction = 0.0;    // [-] the share of the cycle's intervals in events
    double baseline = 0.0;          // [J] the median kinetic energy of the cycle's records
    double friction = 0.0;          // [J] frictional dissipation in events
    double damping = 0.0;           // [J] local-damping dissipation in events
    double viscous = 0.0;           // [J] dashpot dissipation in events
    double friction_total = 0.0, damping_total = 0.0, viscous_total = 0.0;  // [J] over the cycle
};

// The split of one cycle by the detector above. threshold > 1 (a burst is kinetic energy above
// threshold times the cycle's median); throws std::invalid_argument for threshold <= 1 or
// columns of different lengths. Fewer than 2 records: an empty split.
EventSplit split_events(const EventSeries& series, double threshold);

}  // namespace vpp
