// events.cpp — the text form of the cosim events (docs/cosim.md, "The event
// log as text"): decimal fields, except words and CRCs in 8 hex digits.
#include "events.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace {

struct KindInfo {
    const char *name, *unit;
    int fields;
    int hex_field;               // the field printed as 0x%08x, or -1
};

const KindInfo kinds[EV_KINDS] = {
    {"push", "fifo", 2, 1},     {"pop", "parser", 2, 1},    {"load", "parser", 3, -1},
    {"start", "engine", 2, -1}, {"cell", "engine", 8, -1},  {"end", "engine", 2, -1},
    {"fill", "fill", 6, -1},    {"write", "pipe", 8, -1},   {"frame", "frame_store", 3, 2},
};

}  // namespace

bool Event::operator==(const Event &o) const
{
    return cycle == o.cycle && kind == o.kind && !std::memcmp(f, o.f, sizeof f);
}

bool Event::operator<(const Event &o) const
{
    if (cycle != o.cycle)
        return cycle < o.cycle;
    if (kind != o.kind)
        return kind < o.kind;
    return std::memcmp(f, o.f, sizeof f) < 0;
}

const char *event_kind_name(int kind) { return kind >= 0 && kind < EV_KINDS ? kinds[kind].name : "?"; }
const char *event_unit(int kind) { return kind >= 0 && kind < EV_KINDS ? kinds[kind].unit : "?"; }
int event_fields(int kind) { return kind >= 0 && kind < EV_KINDS ? kinds[kind].fields : 0; }

std::string event_format(const Event &e)
{
    char buf[256];
    int n = std::snprintf(buf, sizeof buf, "%" PRIu64 " %s", e.cycle, event_kind_name(e.kind));
    for (int i = 0; i < event_fields(e.kind) && n > 0 && n < (int)sizeof buf; i++)
        n += std::snprintf(buf + n, sizeof buf - (size_t)n,
                           i == kinds[e.kind].hex_field ? " 0x%08" PRIx64 : " %" PRIu64, e.f[i]);
    return buf;
}

bool event_parse(const std::string &line, Event &e, std::string &why)
{
    std::istringstream in(line);
    std::string name;
    e = Event();
    if (!(in >> e.cycle >> name)) {
        why = "expected '<cycle> <kind> ...'";
        return false;
    }
    e.kind = -1;
    for (int k = 0; k < EV_KINDS; k++)
        if (name == kinds[k].name)
            e.kind = k;
    if (e.kind < 0) {
        why = "unknown event kind '" + name + "'";
        return false;
    }
    for (int i = 0; i < kinds[e.kind].fields; i++) {
        std::string tok;
        if (!(in >> tok)) {
            why = std::string(name) + " has " + std::to_string(i) + " fields, expected " +
                  std::to_string(kinds[e.kind].fields);
            return false;
        }
        char *end = nullptr;
        e.f[i] = std::strtoull(tok.c_str(), &end, i == kinds[e.kind].hex_field ? 16 : 10);
        if (!end || *end) {
            why = "field " + std::to_string(i + 1) + " '" + tok + "' is not a number";
            return false;
        }
    }
    std::string extra;
    if (in >> extra) {
        why = "more fields than a " + name + " event has";
        return false;
    }
    return true;
}
