// events.h — the events of the cosim contract (docs/cosim.md) as the bench
// handles them: one struct for every kind, the text form of the model's
// --events log (parse and format), and the unit each kind belongs to.
#ifndef ALB_BENCH_EVENTS_H
#define ALB_BENCH_EVENTS_H

#include <cstdint>
#include <string>

enum EventKind { EV_PUSH, EV_POP, EV_LOAD, EV_START, EV_CELL, EV_END, EV_FILL, EV_WRITE,
                 EV_FRAME, EV_KINDS };

struct Event {
    uint64_t cycle = 0;
    int kind = EV_PUSH;
    uint64_t f[8] = {};          // the fields in the order of the text form

    bool operator==(const Event &o) const;
    bool operator<(const Event &o) const;
};

const char *event_kind_name(int kind);
// The unit of docs/microarchitecture.md whose output the event is.
const char *event_unit(int kind);
// How many fields the kind has in the text form.
int event_fields(int kind);
// "<cycle> <kind> <fields>", as albatros --events writes it (no newline).
std::string event_format(const Event &e);
// One line of the text form; false with a reason if it is not one.
bool event_parse(const std::string &line, Event &e, std::string &why);

#endif
