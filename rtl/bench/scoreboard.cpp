// scoreboard.cpp — per-cycle comparison of event sets, kind by kind in the
// contract's order, naming the first event found on one side only.
#include "scoreboard.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

std::string Mismatch::describe() const
{
    char head[128];
    std::snprintf(head, sizeof head, "cycle %" PRIu64 ": unit %s: event %s", cycle, unit.c_str(),
                  event.c_str());
    return std::string(head) + "\n  expected " + expected + "\n  actual   " + actual;
}

bool Scoreboard::cycle(uint64_t t, std::vector<Event> expected, std::vector<Event> actual,
                       Mismatch &m)
{
    for (Event &e : expected)
        if (e.kind == EV_FRAME) {
            pending_.push_back({e.f[0], e.f[2]});
            e.f[2] = 0;      // the CRC is matched when the RTL reports it
        }
    for (Event &e : actual)
        if (e.kind == EV_FRAME)
            e.f[2] = 0;
    std::sort(expected.begin(), expected.end());
    std::sort(actual.begin(), actual.end());
    if (expected == actual) {
        matched_ += expected.size();
        for (const Event &e : expected)
            by_kind_[e.kind]++;
        return true;
    }
    // the first kind (in the contract's order) whose events differ, and its
    // first event present on one side only
    for (int k = 0; k < EV_KINDS; k++) {
        std::vector<Event> a, b;
        for (const Event &e : expected)
            if (e.kind == k)
                a.push_back(e);
        for (const Event &e : actual)
            if (e.kind == k)
                b.push_back(e);
        if (a == b)
            continue;
        size_t i = 0;
        while (i < a.size() && i < b.size() && a[i] == b[i])
            i++;
        m.cycle = t;
        m.unit = event_unit(k);
        m.event = event_kind_name(k);
        auto show = [](const std::vector<Event> &v, size_t i) {
            return i < v.size() ? event_format(v[i]) : std::string("(none)");
        };
        m.expected = show(a, i);
        m.actual = show(b, i);
        char counts[96];
        std::snprintf(counts, sizeof counts, "   [%zu expected, %zu actual %s events this cycle]",
                      a.size(), b.size(), event_kind_name(k));
        m.actual += counts;
        return false;
    }
    return false;   // unreachable: the sets differ in some kind
}

bool Scoreboard::crc(uint64_t t, uint32_t number, uint32_t value, Mismatch &m)
{
    char got[96];
    std::snprintf(got, sizeof got, "crc of frame %u = 0x%08x", number, value);
    if (pending_.empty()) {
        m = {t, "frame_crc", "crc", "(no frame waiting for its CRC)", got};
        return false;
    }
    Crc c = pending_.front();
    pending_.pop_front();
    if (c.number != number || c.value != value) {
        char want[96];
        std::snprintf(want, sizeof want, "crc of frame %" PRIu64 " = 0x%08" PRIx64, c.number,
                      c.value);
        m = {t, "frame_crc", "crc", want, got};
        return false;
    }
    crcs_++;
    return true;
}
