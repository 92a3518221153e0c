// scoreboard.h — compares the events of the RTL with the model's, cycle by
// cycle (docs/cosim.md, "Order"): in each cycle the set of events of each kind
// must be equal (the writes of one cycle in any order); frame CRCs, which the
// RTL's output stage reports after the frame event, are matched in frame
// order whenever they come.  Fed per-cycle event lists, so it does not care
// where they come from: a text log today, the library's step-and-compare API
// later.
#ifndef ALB_BENCH_SCOREBOARD_H
#define ALB_BENCH_SCOREBOARD_H

#include "events.h"

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

struct Mismatch {
    uint64_t cycle = 0;
    std::string unit, event, expected, actual;
    std::string describe() const;
};

class Scoreboard {
public:
    // One cycle's events; false at the first difference, described in m.
    // The frame events' CRCs are set aside for crc() to match.
    bool cycle(uint64_t t, std::vector<Event> expected, std::vector<Event> actual, Mismatch &m);
    // The RTL reported frame `number`'s CRC in cycle t.
    bool crc(uint64_t t, uint32_t number, uint32_t value, Mismatch &m);
    size_t crcs_pending() const { return pending_.size(); }
    // The RTL's output stage gave up the oldest frame waiting for its CRC
    // (a scan-out overrun): that CRC cannot be checked.
    void crc_lost() { if (!pending_.empty()) { pending_.pop_front(); lost_++; } }
    uint64_t crcs_lost() const { return lost_; }
    uint64_t matched() const { return matched_; }
    uint64_t matched(int kind) const { return by_kind_[kind]; }
    uint64_t crcs_matched() const { return crcs_; }

private:
    struct Crc {
        uint64_t number, value;
    };
    std::deque<Crc> pending_;
    uint64_t matched_ = 0, crcs_ = 0, lost_ = 0;
    uint64_t by_kind_[EV_KINDS] = {};
};

#endif
