// cosim.cpp — the Verilator bench of the VP RTL (rtl/README.md): drives the
// RTL's FIFO write port at the cycles of the model's `push` events, emulates
// the external frame-store memory (rtl/bench/alb_frame_mem.sv), and compares
// the RTL's events with the model's cycle by cycle through the scoreboard.
// The model's events come from its event log (albatros vp STREAM --fidelity
// cycle --events FILE), or from libalbatros in this process, stepped a clock
// at a time beside the RTL (docs/cosim.md).  At the first divergence it prints
// the cycle, unit, event, expected and actual, and runs again with a waveform
// of the cycles before it.
//
//   cosim --events MODEL.log [--stream S.stream] [options]
//   cosim --model PROFILE [--set KEY=VALUE ...] --stream S.stream [options]
//   cosim --stream S.stream --expect-error CODE@WORD      (a malformed stream)
//   options: [--log RTL.log] [--dump PREFIX] [--vcd F.vcd] [--window N]
//            [--trace-all F.vcd] [--json]
//
// Exit status: 0 every event and CRC matched, 1 a divergence (or an RTL
// error), 2 bad usage or input.
#include "Valb_bench_top.h"
#include "Valb_bench_top__Syms.h"   // the memory model's arrays, for --dump
#include "events.h"
#include "scoreboard.h"
#include "stream_file.h"
#include "verilated.h"
#include "verilated_vcd_c.h"

extern "C" {   // the public headers have no C++ guards of their own
#include <albatros/model.h>
}

#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "vbits.h"

namespace {

// Where the model's events come from, a cycle at a time.
class EventSource {
public:
    virtual ~EventSource() = default;
    virtual bool failed() const = 0;
    virtual const std::string &error() const = 0;
    // No event after the last one taken.
    virtual bool done() const = 0;
    virtual uint64_t last_cycle() const = 0;
    // The events of cycle t, pushes included (cycles before t taken already).
    virtual void take(uint64_t t, std::vector<Event> &out) = 0;
};

// The model's event log (albatros ... --events FILE).
class LogReader : public EventSource {
public:
    bool open(const char *path)
    {
        path_ = path;
        in_.open(path);
        if (!in_)
            return false;
        advance();
        return true;
    }
    bool failed() const override { return !error_.empty(); }
    const std::string &error() const override { return error_; }
    bool done() const override { return eof_; }
    uint64_t last_cycle() const override { return last_; }
    void take(uint64_t t, std::vector<Event> &out) override
    {
        out.clear();
        while (!eof_ && !failed() && next_.cycle == t) {
            out.push_back(next_);
            advance();
        }
    }

private:
    void advance()
    {
        std::string line;
        while (std::getline(in_, line)) {
            lineno_++;
            if (line.empty() || line[0] == '#')
                continue;
            std::string why;
            Event e;
            if (!event_parse(line, e, why)) {
                error_ = path_ + ":" + std::to_string(lineno_) + ": " + why;
                eof_ = true;
                return;
            }
            if (have_ && e.cycle < next_.cycle) {
                error_ = path_ + ":" + std::to_string(lineno_) + ": cycle " +
                         std::to_string(e.cycle) + " after cycle " + std::to_string(next_.cycle);
                eof_ = true;
                return;
            }
            next_ = e;
            last_ = e.cycle;
            have_ = true;
            return;
        }
        eof_ = true;
    }
    std::string path_, error_;
    std::ifstream in_;
    Event next_;
    uint64_t last_ = 0, lineno_ = 0;
    bool eof_ = false, have_ = false;
};

// The cycle model of libalbatros in this process (include/albatros/model.h):
// its GP output stage is the producer, every event recorded, one clock a call.
class ModelSource : public EventSource {
public:
    ~ModelSource() override { alb_model_destroy(m_); }
    bool open(const char *profile, const std::vector<const char *> &sets,
              const std::vector<uint32_t> &words)
    {
        alb_model_config c;
        alb_model_config_default(&c);
        c.events = ALB_EV_ALL;
        c.name = "the stream";
        std::vector<const char *> ov(sets);
        ov.push_back(nullptr);
        alb_diag d;
        alb_diag_init(&d, nullptr);
        if (alb_model_open(&m_, profile, ov.data(), &c, &d)) {
            error_ = std::string("the model: ") + d.msg;
            return false;
        }
        if (alb_model_push(m_, words.data(), words.size()) != words.size()) {
            error_ = std::string("the model took only part of the stream: ") +
                     alb_model_error(m_);
            return false;
        }
        return true;
    }
    bool failed() const override { return !error_.empty(); }
    const std::string &error() const override { return error_; }
    bool done() const override { return alb_model_done(m_); }
    uint64_t last_cycle() const override { return last_; }
    void take(uint64_t t, std::vector<Event> &out) override
    {
        out.clear();
        if (alb_model_done(m_))
            return;
        if (alb_model_cycle(m_) != t || alb_model_step(m_, 1)) {
            error_ = std::string("the model at cycle ") + std::to_string(t) + ": " +
                     alb_model_error(m_);
            return;
        }
        const alb_event *ev;
        size_t n = alb_model_events(m_, &ev);
        for (size_t i = 0; i < n; i++)
            out.push_back(convert(ev[i]));
        alb_model_consume(m_, n);
        if (n)
            last_ = t;
    }

private:
    static Event convert(const alb_event &a)
    {
        Event e;
        e.cycle = a.cycle;
        e.kind = __builtin_ctz(a.kind);      // ALB_EV_PUSH ... ALB_EV_FRAME: bits 0 .. 8
        auto set = [&](std::initializer_list<uint64_t> f) {
            int i = 0;
            for (uint64_t x : f)
                e.f[i++] = x;
        };
        switch (e.kind) {
        case EV_PUSH:
        case EV_POP: set({a.index, a.word}); break;
        case EV_LOAD: set({a.face, a.slot, a.edges}); break;
        case EV_START:
        case EV_END: set({a.face, a.slot}); break;
        case EV_CELL: set({a.face, a.x, a.y, a.wl, a.hl, a.level, a.result, a.edges}); break;
        case EV_FILL: set({a.face, a.x, a.y, a.wl, a.hl, a.level}); break;
        case EV_WRITE:
            set({a.x, a.y, a.depth, a.rgb[0], a.rgb[1], a.rgb[2], a.face, a.level});
            break;
        default: set({a.number, a.cycles, a.crc}); break;
        }
        return e;
    }
    alb_model *m_ = nullptr;
    std::string error_;
    uint64_t last_ = 0;
};

// The RTL's log in the model's format: lines held back from a frame event
// until its CRC is known (the output stage reports it later).
class LogWriter {
public:
    bool open(const char *path)
    {
        if (!path)
            return true;
        f_ = std::fopen(path, "w");
        return f_ != nullptr;
    }
    ~LogWriter() { close(); }
    void add(const Event &e)
    {
        if (!f_)
            return;
        if (e.kind == EV_FRAME)
            frames_.push_back(lines_.size() + flushed_);
        held_.push_back(e);
        lines_.push_back(event_format(e));
        flush();
    }
    void crc(uint32_t value)
    {
        if (!f_ || next_crc_ >= frames_.size())
            return;
        size_t at = frames_[next_crc_++] - flushed_;
        held_[at].f[2] = value;
        lines_[at] = event_format(held_[at]);
        flush();
    }
    bool close()
    {
        if (!f_)
            return true;
        next_crc_ = frames_.size();    // what never got a CRC goes out as it is
        flush();
        bool ok = !std::ferror(f_);
        ok = std::fclose(f_) == 0 && ok;
        f_ = nullptr;
        return ok;
    }

private:
    void flush()
    {
        size_t upto = next_crc_ < frames_.size() ? frames_[next_crc_] - flushed_ : lines_.size();
        for (size_t i = 0; i < upto; i++)
            std::fprintf(f_, "%s\n", lines_[i].c_str());
        lines_.erase(lines_.begin(), lines_.begin() + (long)upto);
        held_.erase(held_.begin(), held_.begin() + (long)upto);
        flushed_ += upto;
    }
    std::FILE *f_ = nullptr;
    std::vector<std::string> lines_;
    std::vector<Event> held_;
    std::vector<size_t> frames_;   // absolute line numbers of frame events
    size_t next_crc_ = 0, flushed_ = 0;
};

// The RTL's frame k as docs/cosim.md's frame-store dump (`$writememh` text,
// one 128-bit record a pixel, row 0 first): the display store resolved as the
// output stage does (docs/vp.md §6) — colour the mean of the pixel's samples,
// a sample of another frame's tag or of depth 0 having the background; depth,
// face and level those of the nearest sample, ties the first in raster order.
// Read from the memory model right after the frame's retirement, before the
// scan-out clears it.
bool dump_frame(const Valb_bench_top &v, uint64_t k, uint64_t bg, const std::string &path)
{
    const unsigned w = v.p_width, h = v.p_height, aa = v.p_aa, cb = v.p_colour_bits;
    const unsigned db = v.p_depth_bits, tb = v.p_tag_bits;
    const unsigned lw = (unsigned)__builtin_ctz(w) + aa, lh = (unsigned)__builtin_ctz(h) + aa;
    const uint64_t ns = 1ull << (2 * aa), store = (k & 1) << (lw + lh);
    const uint64_t tag = k & ((1ull << tb) - 1), dmask = (1ull << db) - 1;
    const auto *mem = v.alb_bench_top->u_mem;
    std::FILE *f = std::fopen(path.c_str(), "w");
    if (!f)
        return false;
    std::fprintf(f, "// RTL frame %" PRIu64 ", %ux%u: face depth R G B level coverage (docs/cosim.md)\n",
                 k, w, h);
    for (uint64_t p = 0; p < (uint64_t)w * h; p++) {
        uint64_t sum[3] = {0, 0, 0}, best = 0, face = 0xFFFFFFFF, level = 255, covered = 0;
        for (uint64_t s = 0; s < ns; s++) {
            uint64_t a = store | p << (2 * aa) | s;
            uint64_t z = bits(mem->depth[a], 0, db + tb), d = z & dmask;
            bool in = d != 0 && z >> db == tag;
            const auto &c = mem->colour[a];
            for (unsigned ch = 0; ch < 3; ch++)
                sum[ch] += in ? bits(c, 40 + (2 - ch) * cb, cb) : bg >> (2 - ch) * cb & ((1u << cb) - 1);
            covered += in;
            if (in && d > best) {
                best = d;
                face = bits(c, 8, 32);
                level = bits(c, 0, 8);
            }
        }
        uint64_t rgb[3];
        for (unsigned ch = 0; ch < 3; ch++)
            rgb[ch] = (sum[ch] + ns / 2) >> (2 * aa);
        std::fprintf(f, "%08" PRIx64 "%08" PRIx64 "%04" PRIx64 "%04" PRIx64 "%04" PRIx64 "%02" PRIx64
                     "%02" PRIx64 "\n", face, best, rgb[0], rgb[1], rgb[2], level, covered);
    }
    bool ok = !std::ferror(f);
    return std::fclose(f) == 0 && ok;
}

struct Options {
    const char *events = nullptr, *stream = nullptr, *log = nullptr, *vcd = nullptr;
    const char *trace_all = nullptr, *profile = nullptr, *expect_error = nullptr;
    const char *dump = nullptr;         // PREFIX: PREFIX.NNNN.memh a frame
    std::vector<const char *> sets;
    uint64_t window = 200;
    bool json = false;
};

struct Result {
    enum { OK, DIVERGED, RTL_ERROR, INPUT } status = OK;
    Mismatch m;
    std::string message;
    uint64_t cycles = 0, frames = 0, events = 0, crcs = 0, lost = 0;
    double seconds = 0, rtl_seconds = 0;     // the whole run; the RTL's evaluations alone
};

// The RTL's events of this cycle (outputs after the clock-low evaluation).
void rtl_events(const Valb_bench_top &v, uint64_t t, std::vector<Event> &out)
{
    out.clear();
    auto add = [&](int kind, std::initializer_list<uint64_t> f) {
        Event e;
        e.cycle = t;
        e.kind = kind;
        int i = 0;
        for (uint64_t x : f)
            e.f[i++] = x;
        out.push_back(e);
    };
    auto cell = [](uint64_t c, int field) {   // rtl/alb_defs.svh, CELL_*
        static const unsigned lo[5] = {0, 16, 32, 37, 42}, w[5] = {16, 16, 5, 5, 5};
        return c >> lo[field] & ((1ull << w[field]) - 1);
    };
    if (v.ev_pop)
        add(EV_POP, {v.ev_pop_index, v.ev_pop_word});
    if (v.ev_load)
        add(EV_LOAD, {v.ev_load_face, v.ev_load_slot, v.ev_load_edges});
    if (v.ev_start)
        add(EV_START, {v.ev_engine_face, v.ev_engine_slot});
    if (v.ev_cell) {
        uint64_t c = v.ev_cell_cell;
        add(EV_CELL, {v.ev_engine_face, cell(c, 0), cell(c, 1), cell(c, 2), cell(c, 3), cell(c, 4),
                      v.ev_cell_result, v.ev_cell_edges});
    }
    if (v.ev_end)
        add(EV_END, {v.ev_engine_face, v.ev_engine_slot});
    if (v.ev_fill) {
        uint64_t c = v.ev_fill_cell;
        add(EV_FILL, {v.ev_fill_face, cell(c, 0), cell(c, 1), cell(c, 2), cell(c, 3), cell(c, 4)});
    }
    const unsigned rate = v.p_fill_rate, db = v.p_depth_bits, cb = v.p_colour_bits;
    for (unsigned j = 0; j < rate; j++) {
        if (!bits(v.ev_write, j, 1))
            continue;
        unsigned base = 3 * cb * j;
        add(EV_WRITE, {bits(v.ev_write_x, 16 * j, 16), bits(v.ev_write_y, 16 * j, 16),
                       bits(v.ev_write_depth, db * j, db), bits(v.ev_write_rgb, base + 2 * cb, cb),
                       bits(v.ev_write_rgb, base + cb, cb), bits(v.ev_write_rgb, base, cb),
                       v.ev_write_face, v.ev_write_level});
    }
    if (v.ev_frame)
        add(EV_FRAME, {v.ev_frame_number, v.ev_frame_cycles, 0});
}

const char *error_name(unsigned code)
{
    static const char *const names[] = {
        "none", "not a packet opcode", "packet out of place", "bad CONFIG",
        "CONFIG formats differ from the profile", "reserved bits set", "too many edges",
        "form exponent or mantissa out of range", "edge intercept beyond 3.F",
        "face count", "texture size, or a texture never loaded", "fog far not beyond fog near",
        "texture memory full (TEX_WORDS)", "a word after END", "word pushed into a full FIFO",
        "more FRAMEs ahead than FRAME_QUEUE",
        "frame tags could alias: 2^(TAG_BITS-1) - 1 scan-outs of one store cut off in a row",
        "needs a unit this build leaves out (SHADE_UNIT, TEX_UNIT, FOG_UNIT)"};
    return code < sizeof names / sizeof names[0] ? names[code] : "?";
}

// One run of the RTL against the log; a trace of cycles [from, to] if vcd.
Result run(const Options &o, const std::vector<uint32_t> *stream, const char *vcd, uint64_t from,
           uint64_t to, bool write_log)
{
    Result r;
    std::unique_ptr<EventSource> source;
    if (o.profile) {
        auto ms = std::make_unique<ModelSource>();
        if (!ms->open(o.profile, o.sets, *stream)) {
            r.status = Result::INPUT;
            r.message = ms->error();
            return r;
        }
        source = std::move(ms);
    } else {
        auto log = std::make_unique<LogReader>();
        if (!log->open(o.events)) {
            r.status = Result::INPUT;
            r.message = std::string(o.events) + ": cannot open: " + std::strerror(errno);
            return r;
        }
        source = std::move(log);
    }
    EventSource &model = *source;
    LogWriter log;
    if (write_log && !log.open(o.log)) {
        r.status = Result::INPUT;
        r.message = std::string(o.log) + ": cannot create: " + std::strerror(errno);
        return r;
    }
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Valb_bench_top>(ctx.get());
    std::unique_ptr<VerilatedVcdC> tfp;
    if (vcd) {
        ctx->traceEverOn(true);
        tfp = std::make_unique<VerilatedVcdC>();
        top->trace(tfp.get(), 99);
        tfp->open(vcd);
    }
    Scoreboard sb;
    bench_reset(*top);
    const uint64_t pixels = (uint64_t)top->p_width * top->p_height;
    const uint64_t scan = pixels / top->p_scan_pixels + 16;   // the last CRC after the last frame
    std::vector<Event> expected, actual, mine;
    size_t next_word = 0;
    uint64_t frames_retired = 0;
    std::chrono::steady_clock::duration in_rtl{};
    auto eval = [&]() {
        auto e0 = std::chrono::steady_clock::now();
        top->eval();
        in_rtl += std::chrono::steady_clock::now() - e0;
    };
    auto t0 = std::chrono::steady_clock::now();
    uint64_t t = 0;
    for (;; t++) {
        model.take(t, mine);
        if (model.failed()) {
            r.status = Result::INPUT;
            r.message = model.error();
            break;
        }
        // the producer: the model's pushes of this cycle
        top->in_valid = 0;
        expected.clear();
        for (const Event &e : mine) {
            if (e.kind != EV_PUSH) {
                expected.push_back(e);
                continue;
            }
            if (top->in_valid || e.f[0] != next_word ||
                (stream && (e.f[0] >= stream->size() || (*stream)[e.f[0]] != e.f[1]))) {
                r.status = Result::INPUT;
                r.message = "the log's push at cycle " + std::to_string(t) + " (word " +
                            std::to_string(e.f[0]) + ") does not follow the stream";
                break;
            }
            top->in_valid = 1;
            top->in_data = (uint32_t)e.f[1];
            next_word++;
        }
        if (r.status != Result::OK)
            break;
        top->clk = 0;
        eval();
        if (tfp && t >= from && t <= to)
            tfp->dump(2 * t);
        if (top->cycle != t) {
            r.status = Result::INPUT;
            r.message = "the RTL's cycle counter reads " + std::to_string(top->cycle) +
                        " in bench cycle " + std::to_string(t);
            break;
        }
        if (top->in_valid && top->in_full) {
            r.status = Result::DIVERGED;
            r.m = {t, "fifo", "push", "room for word " + std::to_string(next_word - 1),
                   "the RTL's FIFO is full"};
            break;
        }
        rtl_events(*top, t, actual);
        for (const Event &e : actual)
            log.add(e);
        if (!sb.cycle(t, expected, actual, r.m)) {
            r.status = Result::DIVERGED;
            break;
        }
        if (top->ev_crc) {
            log.crc(top->ev_crc_value);
            if (!sb.crc(t, top->ev_crc_number, top->ev_crc_value, r.m)) {
                r.status = Result::DIVERGED;
                break;
            }
        }
        if (top->ev_scan_overrun)
            sb.crc_lost();
        if (top->error) {
            r.status = Result::RTL_ERROR;
            r.message = "cycle " + std::to_string(t) + ": the RTL reports error " +
                        std::to_string(top->error_code) + " (" + error_name(top->error_code) +
                        ") at word " + std::to_string(top->error_word);
            break;
        }
        const bool retired = top->ev_frame;
        const uint64_t bg = top->dbg_retire_bg;
        top->clk = 1;
        eval();
        if (tfp && t >= from && t <= to)
            tfp->dump(2 * t + 1);
        if (retired && write_log && o.dump) {
            char name[32];
            std::snprintf(name, sizeof name, ".%04" PRIu64 ".memh", frames_retired);
            if (!dump_frame(*top, frames_retired, bg, o.dump + std::string(name))) {
                r.status = Result::INPUT;
                r.message = std::string(o.dump) + name + ": cannot write: " + std::strerror(errno);
                break;
            }
        }
        frames_retired += retired;
        if (model.done() && t >= model.last_cycle()) {
            if (!sb.crcs_pending())
                break;
            if (t > model.last_cycle() + scan) {
                r.status = Result::DIVERGED;
                r.m = {t, "frame_crc", "crc", "the CRC of the last frames",
                       std::to_string(sb.crcs_pending()) + " never reported"};
                break;
            }
        }
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.rtl_seconds = std::chrono::duration<double>(in_rtl).count();
    r.cycles = t + 1;
    r.events = sb.matched();
    r.frames = sb.matched(EV_FRAME);
    r.crcs = sb.crcs_matched();
    r.lost = sb.crcs_lost();
    top->final();
    if (tfp)
        tfp->close();
    if (write_log && !log.close() && r.status == Result::OK) {
        r.status = Result::INPUT;
        r.message = std::string(o.log) + ": write error";
    }
    return r;
}

// --expect-error CODE@WORD: the stream pushed as fast as the FIFO takes it,
// no model; the RTL must report error CODE at word WORD (a malformed stream).
int expect_error(const std::vector<uint32_t> &words, unsigned code, uint64_t word)
{
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Valb_bench_top>(ctx.get());
    bench_reset(*top);
    size_t next = 0;
    uint64_t t = 0, idle = 0;
    for (; !top->error && idle < 100000; t++) {
        top->eval();
        top->in_valid = next < words.size() && !top->in_full;
        top->in_data = top->in_valid ? words[next] : 0;
        top->eval();
        if (top->error)
            break;
        next += top->in_valid;
        idle = next < words.size() ? 0 : idle + 1;
        top->clk = 1;
        top->eval();
        top->clk = 0;
    }
    top->final();
    if (!top->error) {
        std::printf("cosim: no error in %" PRIu64 " cycles; expected error %u (%s) at word %" PRIu64
                    "\n", t, code, error_name(code), word);
        return 1;
    }
    bool ok = top->error_code == code && top->error_word == word;
    std::printf("cosim: error %u (%s) at word %u in cycle %" PRIu64 "%s\n", top->error_code,
                error_name(top->error_code), top->error_word, t,
                ok ? "" : (", expected error " + std::to_string(code) + " at word " +
                           std::to_string(word)).c_str());
    return ok ? 0 : 1;
}

int usage()
{
    std::fprintf(stderr,
                 "usage: cosim --events MODEL.log [--stream S.stream] [options]\n"
                 "       cosim --model PROFILE [--set KEY=VALUE ...] --stream S.stream [options]\n"
                 "       cosim --stream S.stream --expect-error CODE@WORD\n"
                 "options: [--log RTL.log] [--dump PREFIX] [--vcd FAIL.vcd] [--window N]\n"
                 "         [--trace-all T.vcd] [--json]\n");
    return 2;
}

}  // namespace

int main(int argc, char **argv)
{
    Options o;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto value = [&]() -> const char * { return i + 1 < argc ? argv[++i] : nullptr; };
        const char *v = nullptr;
        if (a == "--events" && (v = value()))
            o.events = v;
        else if (a == "--stream" && (v = value()))
            o.stream = v;
        else if (a == "--log" && (v = value()))
            o.log = v;
        else if (a == "--vcd" && (v = value()))
            o.vcd = v;
        else if (a == "--trace-all" && (v = value()))
            o.trace_all = v;
        else if (a == "--window" && (v = value()))
            o.window = std::strtoull(v, nullptr, 10);
        else if (a == "--model" && (v = value()))
            o.profile = v;
        else if (a == "--set" && (v = value()))
            o.sets.push_back(v);
        else if (a == "--dump" && (v = value()))
            o.dump = v;
        else if (a == "--expect-error" && (v = value()))
            o.expect_error = v;
        else if (a == "--json")
            o.json = true;
        else {
            std::fprintf(stderr, "cosim: unknown or incomplete option '%s'\n", a.c_str());
            return usage();
        }
    }
    if (o.expect_error ? (o.events || o.profile || !o.stream)
                       : (!o.events == !o.profile || (o.profile && !o.stream)) ||
        (!o.sets.empty() && !o.profile))
        return usage();
    std::vector<uint32_t> words;
    if (o.stream) {
        std::string err;
        words = read_stream(o.stream, err);
        if (!err.empty()) {
            std::fprintf(stderr, "cosim: %s\n", err.c_str());
            return 2;
        }
    }
    if (o.expect_error) {
        unsigned code;
        unsigned long long word;
        char extra;
        if (std::sscanf(o.expect_error, "%u@%llu%c", &code, &word, &extra) != 2) {
            std::fprintf(stderr, "cosim: --expect-error %s: expected CODE@WORD\n", o.expect_error);
            return 2;
        }
        return expect_error(words, code, word);
    }
    const std::vector<uint32_t> *stream = o.stream ? &words : nullptr;
    Result r = run(o, stream, o.trace_all, 0, UINT64_MAX, true);
    if (r.status == Result::INPUT) {
        std::fprintf(stderr, "cosim: %s\n", r.message.c_str());
        return 2;
    }
    if (r.status == Result::OK) {
        if (o.json)
            std::printf("{\"status\": \"ok\", \"cycles\": %" PRIu64 ", \"events\": %" PRIu64
                        ", \"frames\": %" PRIu64 ", \"crcs\": %" PRIu64 ", \"crcs_unchecked\": %"
                        PRIu64 ", \"seconds\": %.3f, \"cycles_per_second\": %.0f, "
                        "\"rtl_seconds\": %.3f, \"rtl_cycles_per_second\": %.0f}\n",
                        r.cycles, r.events, r.frames, r.crcs, r.lost, r.seconds,
                        r.cycles / r.seconds, r.rtl_seconds, r.cycles / r.rtl_seconds);
        else
            std::printf("cosim: %" PRIu64 " cycles, %" PRIu64 " events and %" PRIu64
                        " frame CRCs match%s (%.2f s, %.0f cycles/s; the RTL alone %.0f cycles/s)\n",
                        r.cycles, r.events, r.crcs,
                        r.lost ? (", " + std::to_string(r.lost) + " CRCs unchecked: the scan-out "
                                  "overran (rtl/README.md)").c_str() : "",
                        r.seconds, r.cycles / r.seconds, r.cycles / r.rtl_seconds);
        return 0;
    }
    uint64_t at = r.status == Result::DIVERGED ? r.m.cycle : r.cycles - 1;
    if (r.status == Result::DIVERGED)
        std::fprintf(stderr, "cosim: divergence at %s\n", r.m.describe().c_str());
    else
        std::fprintf(stderr, "cosim: %s\n", r.message.c_str());
    std::fprintf(stderr, "cosim: %" PRIu64 " events matched before it\n", r.events);
    if (o.vcd) {
        uint64_t from = at > o.window ? at - o.window : 0;
        Result again = run(o, stream, o.vcd, from, at + 4, false);
        (void)again;
        std::fprintf(stderr, "cosim: waveform of cycles %" PRIu64 "..%" PRIu64 " in %s\n", from,
                     at + 4, o.vcd);
    }
    return 1;
}
