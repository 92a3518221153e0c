// top_bench.cpp — the Verilator bench of alb_fpga_top, the board's FPGA
// (rtl/fpga/README.md, "The top's bench"): the FX2's side of its synchronous
// slave FIFOs as firmware/fx2/main.c configures them, the 8051 that fills EP4
// and drains EP8, two unrelated clocks (the VP's and IFCLK), and the C model
// (libalbatros, its FIFO fed by this bench) stepped beside the VP so that
// every RESULT record is checked against the model's frame number, CRC and
// cycle count, and against the stream's FRAME_END counts.
//
//   top_bench --stream S.stream [--profile P] [--set K=V ...] [--vp-khz F]
//             [--ifclk-khz F] [--phase-ps N] [--seed N] [--records FILE]
//             [--resume AT] [--reset AT] [--expect-error WORD[:CODE]]
//             [--flag-lag N] [--ep8-stall-every N] [--ep8-hold N] [--ep4-pace N]
//             [--restart-in-record K] [--vcd FILE] [--max-cycles N] [--power-up]
//             [--quiet]
//
// Exit status: 0 every check passed, 1 a check failed, 2 bad usage or input.
#include "Valb_fpga_top_tb.h"
#include "../../bench/stream_file.h"
#include "verilated.h"
#include "verilated_vcd_c.h"

extern "C" {   // the public headers have no C++ guards of their own
#include <albatros/model.h>
}

#include <cerrno>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

// ---- the stream ----

// Where the stream's packets are (docs/word-format.md): the FRAME headers and
// the FRAME_END counts, in order.  Only the lengths are decoded; the VP and
// the model check the rest.
struct StreamMap {
    std::vector<size_t> frame_at;       // word index of each FRAME header
    std::vector<uint32_t> frame_faces;  // each FRAME_END's count
    size_t end_at = 0;                  // the END word
};

bool map_stream(const std::vector<uint32_t> &w, StreamMap &m, std::string &err)
{
    size_t i = 0;
    while (i < w.size()) {
        uint32_t h = w[i];
        size_t len;
        switch (h >> 24) {
        case 0xA5: len = 1 + (h & 0xFFFF); break;
        case 0xA7: {
            unsigned l = h >> 8 & 0xFF;
            if (l > 10) {
                err = "word " + std::to_string(i) + ": TEXTURE of side 2^" + std::to_string(l);
                return false;
            }
            len = 1 + ((size_t)1 << (2 * l));
            break;
        }
        case 0xF0: m.frame_at.push_back(i); len = 5; break;
        case 0xFA: len = 7 + 4 * (h >> 8 & 1) + 8 * (h >> 9 & 1) + 2 * (h >> 16 & 0xFF); break;
        case 0xFE: m.frame_faces.push_back(h & 0xFFFFFF); len = 1; break;
        case 0xFF: m.end_at = i; return i + 1 == w.size() ||
                   (err = "word " + std::to_string(i + 1) + ": words after END", false);
        default:
            err = "word " + std::to_string(i) + ": not a packet header";
            return false;
        }
        i += len;
    }
    err = "the stream has no END";
    return false;
}

// ---- checks ----

struct Failures {
    unsigned count = 0;
    bool quiet = false;
    void fail(const char *fmt, ...) __attribute__((format(printf, 2, 3)))
    {
        if (count++ < 20) {
            va_list ap;
            va_start(ap, fmt);
            std::fputs("top_bench: FAIL: ", stdout);
            std::vprintf(fmt, ap);
            std::fputc('\n', stdout);
            va_end(ap);
        }
    }
};

// A RESULT record as alb_fpga_top sends it: five u32.
struct Result {
    uint32_t frame, crc, cycles_lo, cycles_hi, faces;
};

// ---- the FX2 (CY7C68013A) and its 8051, as firmware/fx2/main.c sets them up ----

struct Fx2Config {
    unsigned flag_lag = 0;          // extra IFCLK edges before a flag shows a change
    unsigned ep8_stall_every = 2;   // every N-th record, the 8051 lets EP8 fill up
    unsigned ep8_hold = 300;        // ... and leaves it full this many IFCLKs
    unsigned ep8_stall_max = 40000; // ... or gives up waiting after this many
    unsigned ep4_pace = 1;          // IFCLKs the 8051 takes per byte it copies into EP4
    unsigned restart_clocks = 48;   // VP_RESTART high (the 8051's ep4_reset): 1 us at 48 MHz
    uint32_t seed = 1;
};

class Fx2 {
public:
    // EP4 and EP8: 512-byte buffers, two each (EP4CFG, EP8CFG); 16-bit beats.
    static constexpr size_t BUF_BEATS = 256;

    struct Packet {
        std::vector<uint16_t> beats;
        int phase;   // the FPGA's reset epoch of its first beat
        bool mixed;  // beats from both sides of a restart
    };

    Fx2(const Fx2Config &c, Failures &f) : c_(c), f_(f), rng_(c.seed) {}

    // The words the 8051 passes on (its WORDS payloads), from the start.
    void source(const std::vector<uint32_t> &words, size_t from, size_t to)
    {
        src_.clear();
        for (size_t i = from; i < to; i++) {
            src_.push_back((uint16_t)words[i]);         // low half first: FD[7:0] is
            src_.push_back((uint16_t)(words[i] >> 16)); // the first byte
        }
        src_next_ = 0;
    }
    // The 8051's fx2_vp_restart: PA1 as given, PA0 high, EP4 reset, PA0 low.
    // EP4's FIFO reset comes some clocks after PA0 rises (FIFORESET = NAKALL,
    // SYNCDELAY, FIFORESET = 0x04: about 16 IFCLKs), PA0 falls after it.  EP8
    // is left as it is, as main.c leaves it.
    void restart(bool new_stream)
    {
        pa1_ = new_stream;
        pa0_ = true;
        st_ = S_RESTART_HIGH;
        busy_until_ = now_ + 16;
        fill_.clear();
        chunk_left_ = 0;
    }
    bool restarting() const { return st_ == S_RESTART_HIGH || st_ == S_RESTART; }
    bool source_done() const { return src_next_ == src_.size() && fill_.empty() && ep4_.empty(); }
    bool ep8_idle() const { return ep8_fill_.empty() && ep8_done_.empty(); }

    // The pins as the FX2 samples them at an IFCLK edge, and what it does.
    template <class Top> void sample(const Top &t, int fpga_phase)
    {
        const bool slrd = !t.slrd_n, slwr = !t.slwr_n, pktend = !t.pktend_n;
        const unsigned adr = t.fifoadr;
        if (now_ == 0 && adr == 0 && (slrd || slwr || pktend)) {
            // the FPGA's flip-flops start at 0, so its active-low strobes are
            // low until its first IFCLK edge; FIFOADR 00 is EP2, whose buffers
            // are the 8051's (manual OUT): the FX2 has nothing there to read,
            // write or end
            std::printf("top_bench: note: IFCLK 0: %s%s%slow with FIFOADR 00 at the FPGA's "
                        "first edge (its flip-flops start at 0; ignored)\n",
                        slrd ? "SLRD " : "", slwr ? "SLWR " : "", pktend ? "PKTEND " : "");
            run_8051();
            now_++;
            return;
        }
        if (slrd && slwr)
            f_.fail("IFCLK %" PRIu64 ": SLRD and SLWR together", now_);
        if (slrd) {
            if (adr != 1)
                f_.fail("IFCLK %" PRIu64 ": SLRD with FIFOADR %u (EP4 is 01)", now_, adr);
            else if (t.sloe_n)
                f_.fail("IFCLK %" PRIu64 ": SLRD with SLOE high: the FPGA cannot see the beat",
                        now_);
            if (ep4_.empty()) {
                f_.fail("IFCLK %" PRIu64 ": SLRD while EP4 is empty (FLAGA low): the FX2 "
                        "ignores it, the FPGA takes a beat that is not there", now_);
                bad_reads_++;
            } else if (adr == 1) {
                Buf &b = ep4_.front();
                if (++b.next == b.beats.size())
                    ep4_.pop_front();   // drained: back to the USB side (main.c)
                beats_read_++;
            }
        }
        if (slwr) {
            if (adr != 3)
                f_.fail("IFCLK %" PRIu64 ": SLWR with FIFOADR %u (EP8 is 11)", now_, adr);
            else if (!t.fpga_fd_oe)
                f_.fail("IFCLK %" PRIu64 ": SLWR while the FPGA does not drive FD", now_);
            else if (ep8_full())
                f_.fail("IFCLK %" PRIu64 ": SLWR while EP8 is full (FLAGB low): beat %04x lost",
                        now_, (unsigned)t.fd_bus);
            else {
                if (ep8_fill_.empty())
                    ep8_phase_ = fpga_phase;
                else if (ep8_phase_ != fpga_phase)
                    ep8_mixed_ = true;
                ep8_fill_.push_back((uint16_t)t.fd_bus);
                if (ep8_fill_.size() > BUF_BEATS)
                    f_.fail("IFCLK %" PRIu64 ": a record longer than EP8's 512-byte buffer", now_);
            }
        }
        if (pktend) {
            if (adr != 3)
                f_.fail("IFCLK %" PRIu64 ": PKTEND with FIFOADR %u (EP8 is 11)", now_, adr);
            else if (ep8_full())
                f_.fail("IFCLK %" PRIu64 ": PKTEND while EP8 is full", now_);
            else if (ep8_fill_.empty())
                f_.fail("IFCLK %" PRIu64 ": PKTEND with no beat written: a zero-length packet",
                        now_);
            else {
                ep8_done_.push_back({ep8_fill_, ep8_phase_, ep8_mixed_});
                ep8_fill_.clear();
                ep8_mixed_ = false;
            }
        }
        run_8051();
        now_++;
    }

    // After the edge: the flags, FD and the port pins as the FX2 drives them
    // until the next edge.  A flag shows the state after the edge that
    // changed it (flag_lag 0), or flag_lag edges later.
    template <class Top> void drive(Top &t)
    {
        flag_hist_[now_ % 8] = (uint8_t)((ep4_.empty() ? 0 : 1) | (ep8_full() ? 0 : 2));
        const uint8_t shown = flag_hist_[(now_ + 8 - c_.flag_lag) % 8];
        t.flaga_n = shown & 1;
        t.flagb_n = shown >> 1 & 1;
        // SLOE enables the FX2's FD drivers; FIFOADR selects what they carry
        // (a beat not in EP4 is garbage, which a read must never see)
        t.fx2_fd_oe = !t.sloe_n;
        t.fx2_fd_out = (t.fifoadr == 1 && !ep4_.empty()) ? ep4_.front().beats[ep4_.front().next]
                                                         : (uint16_t)(0xDEAD ^ now_);
        t.vp_restart = pa0_;
        t.vp_new_stream = pa1_;
    }

    // The bus: never both drivers, and an idle cycle between them.
    template <class Top> void check_bus(const Top &t)
    {
        const bool fx2 = t.fx2_fd_oe, fpga = t.fpga_fd_oe;
        if (fx2 && fpga)
            f_.fail("IFCLK %" PRIu64 ": FX2 and FPGA both drive FD", now_);
        else if ((fx2 && prev_fpga_) || (fpga && prev_fx2_))
            f_.fail("IFCLK %" PRIu64 ": FD changes driver with no idle clock between", now_);
        prev_fx2_ = fx2;
        prev_fpga_ = fpga;
        if (ep8_full())
            full_clocks_++;
        if (ep8_full() && !was_full_)
            full_episodes_++;
        was_full_ = ep8_full();
    }

    // The next record the 8051 took from EP8, if any.
    bool take(Packet &p)
    {
        if (taken_.empty())
            return false;
        p = std::move(taken_.front());
        taken_.pop_front();
        return true;
    }

    uint64_t now() const { return now_; }
    uint64_t beats_read() const { return beats_read_; }
    uint64_t bad_reads() const { return bad_reads_; }
    uint64_t full_episodes() const { return full_episodes_; }
    uint64_t full_clocks() const { return full_clocks_; }
    uint64_t empty_waits() const { return empty_waits_; }
    size_t ep8_fill_beats() const { return ep8_fill_.size(); }

private:
    struct Buf {
        std::vector<uint16_t> beats;
        size_t next = 0;
    };
    enum State { S_IDLE, S_COPY, S_COPIED, S_WAIT_EMPTY, S_FIFORESET, S_RESTART_HIGH, S_RESTART };

    unsigned rnd(unsigned n) { return n ? (unsigned)(rng_() % n) : 0; }
    bool ep8_full() const { return ep8_done_.size() >= 2; }

    // The 8051's main loop, an IFCLK at a time: EP4 is filled as fx2_vp_words
    // and ep4_commit do it (a buffer committed when full and at the end of
    // each EP2 packet; after two, wait for the FPGA to empty EP4, then a FIFO
    // reset); EP8 is polled (poll_ep8) and its records taken.
    void run_8051()
    {
        poll_ep8();
        if (now_ < busy_until_)
            return;
        switch (st_) {
        case S_RESTART_HIGH:
            ep4_.clear();
            committed_ = 0;
            st_ = S_RESTART;
            busy_until_ = now_ + (c_.restart_clocks > 16 ? c_.restart_clocks - 16 : 0);
            break;
        case S_RESTART:
            pa0_ = false;
            st_ = S_IDLE;
            break;
        case S_IDLE:
            if (src_next_ < src_.size()) {
                // the next EP2 packet's words: up to 123 (a 492-byte payload),
                // after the host's and the core's time
                unsigned words = rnd(4) ? 1 + rnd(123) : 1 + rnd(8);
                chunk_left_ = std::min<size_t>(2 * words, src_.size() - src_next_);
                busy_until_ = now_ + rnd(4) * rnd(400);
                st_ = S_COPY;
            }
            break;
        case S_COPY:
            copy_ = std::min(chunk_left_, BUF_BEATS - fill_.size());
            busy_until_ = now_ + 2 * copy_ * c_.ep4_pace;
            st_ = S_COPIED;
            break;
        case S_COPIED:
            fill_.insert(fill_.end(), src_.begin() + (long)src_next_,
                         src_.begin() + (long)(src_next_ + copy_));
            src_next_ += copy_;
            chunk_left_ -= copy_;
            if (fill_.size() == BUF_BEATS || chunk_left_ == 0) {
                ep4_.push_back({fill_, 0});   // EP4BCL: committed to the slave FIFO
                fill_.clear();
                if (++committed_ == 2) {
                    st_ = S_WAIT_EMPTY;
                    break;
                }
            }
            st_ = chunk_left_ ? S_COPY : S_IDLE;
            break;
        case S_WAIT_EMPTY:
            if (ep4_.empty()) {
                st_ = S_FIFORESET;
                busy_until_ = now_ + 16;
            } else
                empty_waits_++;
            break;
        case S_FIFORESET:
            committed_ = 0;
            st_ = chunk_left_ ? S_COPY : S_IDLE;
            break;
        }
    }

    // A committed EP8 packet is read after a while; every ep8_stall_every-th
    // time the 8051 is busy until both buffers are full and have stayed full
    // ep8_hold clocks, so that the FPGA meets FLAGB.
    void poll_ep8()
    {
        if (ep8_done_.empty()) {
            take_at_ = 0;
            return;
        }
        if (stalling_ && now_ - stall_from_ > c_.ep8_stall_max)
            stalling_ = false;   // nothing more came: the 8051 is not busy for ever
        if (stalling_) {
            if (!ep8_full()) {
                full_since_ = 0;
                return;
            }
            if (!full_since_)
                full_since_ = now_;
            if (now_ - full_since_ < c_.ep8_hold)
                return;
            stalling_ = false;
            take_at_ = now_;
        }
        if (!take_at_)
            take_at_ = now_ + 20 + rnd(200);
        if (now_ < take_at_)
            return;
        taken_.push_back(std::move(ep8_done_.front()));   // INPKTEND SKIP: the buffer back
        ep8_done_.pop_front();
        take_at_ = 0;
        if (c_.ep8_stall_every && ++records_ % c_.ep8_stall_every == 0) {
            stalling_ = true;
            full_since_ = 0;
            stall_from_ = now_;
        }
    }

    Fx2Config c_;
    Failures &f_;
    std::mt19937 rng_;
    uint64_t now_ = 0, busy_until_ = 0;
    State st_ = S_IDLE;
    std::vector<uint16_t> src_;
    size_t src_next_ = 0, chunk_left_ = 0, copy_ = 0;
    std::vector<uint16_t> fill_;
    unsigned committed_ = 0;
    std::deque<Buf> ep4_;
    std::vector<uint16_t> ep8_fill_;
    int ep8_phase_ = 0;
    bool ep8_mixed_ = false;
    std::deque<Packet> ep8_done_, taken_;
    uint64_t take_at_ = 0, full_since_ = 0, stall_from_ = 0, records_ = 0;
    bool stalling_ = false;
    bool pa0_ = false, pa1_ = false;
    uint8_t flag_hist_[8] = {2, 2, 2, 2, 2, 2, 2, 2};   // EP4 empty, EP8 not full
    bool prev_fx2_ = false, prev_fpga_ = false, was_full_ = false;

    uint64_t beats_read_ = 0, bad_reads_ = 0, full_episodes_ = 0, full_clocks_ = 0,
             empty_waits_ = 0;
};

// ---- options ----

struct Restart {
    bool new_stream;   // RESET (a new stream) or RESUME (from a FRAME)
    uint64_t at;       // when the VP has taken this many words of its phase
    long in_record;    // or: when the FPGA has written this many beats of a record
};

struct Options {
    const char *stream = nullptr;
    const char *profile = "up5k";
    std::vector<const char *> sets;
    double vp_khz = 12000, if_khz = 48000;
    uint64_t phase_ps = 7001;
    const char *records = nullptr;
    const char *vcd = nullptr;
    long long expect_error = -1;
    int expect_code = -1;
    std::vector<Restart> restarts;
    uint64_t max_cycles = 20000000;
    bool quiet = false;
    bool power_up = false;
    Fx2Config fx2;
};

[[noreturn]] void usage(const char *msg)
{
    if (msg)
        std::fprintf(stderr, "top_bench: %s\n", msg);
    std::fprintf(stderr,
                 "usage: top_bench --stream S.stream [--profile P] [--set K=V ...] [--vp-khz F]\n"
                 "                 [--ifclk-khz F] [--phase-ps N] [--seed N] [--records FILE]\n"
                 "                 [--resume AT] [--reset AT] [--restart-in-record K]\n"
                 "                 [--expect-error WORD[:CODE]] [--flag-lag N]\n"
                 "                 [--ep8-stall-every N] [--ep8-hold N] [--ep4-pace N]\n"
                 "                 [--vcd FILE] [--max-cycles N] [--power-up] [--quiet]\n");
    std::exit(2);
}

uint64_t number(const char *opt, const char *s)
{
    char *end;
    errno = 0;
    unsigned long long v = std::strtoull(s, &end, 10);
    if (errno || end == s || *end || *s == '-')
        usage((std::string(opt) + ": expected a whole number, got '" + s + "'").c_str());
    return v;
}

Options parse(int argc, char **argv)
{
    Options o;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto val = [&]() -> const char * {
            if (i + 1 >= argc)
                usage((a + " needs a value").c_str());
            return argv[++i];
        };
        if (a == "--stream") o.stream = val();
        else if (a == "--profile") o.profile = val();
        else if (a == "--set") o.sets.push_back(val());
        else if (a == "--vp-khz") o.vp_khz = (double)number("--vp-khz", val());
        else if (a == "--ifclk-khz") o.if_khz = (double)number("--ifclk-khz", val());
        else if (a == "--phase-ps") o.phase_ps = number("--phase-ps", val());
        else if (a == "--seed") o.fx2.seed = (uint32_t)number("--seed", val());
        else if (a == "--records") o.records = val();
        else if (a == "--vcd") o.vcd = val();
        else if (a == "--resume") o.restarts.push_back({false, number("--resume", val()), -1});
        else if (a == "--reset") o.restarts.push_back({true, number("--reset", val()), -1});
        else if (a == "--restart-in-record")
            o.restarts.push_back({false, 0, (long)number("--restart-in-record", val())});
        else if (a == "--flag-lag") o.fx2.flag_lag = (unsigned)number("--flag-lag", val());
        else if (a == "--ep8-stall-every")
            o.fx2.ep8_stall_every = (unsigned)number("--ep8-stall-every", val());
        else if (a == "--ep8-hold") o.fx2.ep8_hold = (unsigned)number("--ep8-hold", val());
        else if (a == "--ep4-pace") o.fx2.ep4_pace = (unsigned)number("--ep4-pace", val());
        else if (a == "--max-cycles") o.max_cycles = number("--max-cycles", val());
        else if (a == "--quiet") o.quiet = true;
        else if (a == "--power-up") o.power_up = true;
        else if (a == "--expect-error") {
            std::string v = val();
            size_t colon = v.find(':');
            o.expect_error = (long long)number("--expect-error", v.substr(0, colon).c_str());
            if (colon != std::string::npos)
                o.expect_code = (int)number("--expect-error", v.substr(colon + 1).c_str());
        } else
            usage(("unknown option " + a).c_str());
    }
    if (!o.stream)
        usage("--stream is required");
    if (o.fx2.flag_lag > 7)
        usage("--flag-lag: at most 7");
    if (o.vp_khz < 1 || o.if_khz < 1)
        usage("a clock of 0 kHz");
    return o;
}

// ---- one phase of the VP: from a reset to the next ----

// The words the VP is to take after its reset (for a RESUME, the CONFIG the
// top replays and the resent frames), the model beside it, and the records
// it owes.
struct Phase {
    std::vector<uint32_t> words;
    std::vector<uint32_t> faces;     // FRAME_END counts of these words, in order
    size_t first_frame = 0;          // the stream's frame index of the phase's first FRAME
    size_t taken = 0;                // words the VP took
    size_t frames_retired = 0, results_seen = 0;
    alb_model *model = nullptr;
    std::deque<Result> owed;         // retired in the model, RESULT not seen yet
};

uint64_t period_ps(double khz) { return (uint64_t)(1e9 / khz + 0.5); }

int run(const Options &o)
{
    std::string err;
    const std::vector<uint32_t> stream = read_stream(o.stream, err);
    StreamMap map;
    if (!err.empty() || !map_stream(stream, map, err)) {
        std::fprintf(stderr, "top_bench: %s: %s\n", o.stream, err.c_str());
        return 2;
    }
    if (map.frame_at.size() != map.frame_faces.size()) {
        std::fprintf(stderr, "top_bench: %s: %zu FRAMEs, %zu FRAME_ENDs\n", o.stream,
                     map.frame_at.size(), map.frame_faces.size());
        return 2;
    }
    const bool error_case = o.expect_error >= 0;
    std::FILE *rec = nullptr;
    if (o.records && !(rec = std::fopen(o.records, "w"))) {
        std::fprintf(stderr, "top_bench: %s: cannot create: %s\n", o.records, std::strerror(errno));
        return 2;
    }

    Failures f;
    Fx2 fx2(o.fx2, f);
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Valb_fpga_top_tb>(ctx.get());
    std::unique_ptr<VerilatedVcdC> tfp;
    if (o.vcd) {
        ctx->traceEverOn(true);
        tfp = std::make_unique<VerilatedVcdC>();
        top->trace(tfp.get(), 99);
        tfp->set_time_unit("1ps");
        tfp->set_time_resolution("1ps");
        tfp->open(o.vcd);
    }

    // A phase starts at each VP_RESTART: the first is the host's RESET that
    // begins every stream (docs/usb-protocol.md), unless --power-up runs the
    // stream from the FPGA's power-up state alone.
    std::vector<Phase> phases;
    int vp_phase = -1;          // the phase whose model runs (-1: in reset, or none yet)
    int fpga_phase = -1;        // the FX2 side's epoch: rst_if rises counted, from -1
    bool rst_if_was = false;
    size_t next_restart = 0;
    bool restart_pending = !o.power_up, restart_new = true;
    if (o.power_up) {
        phases.resize(1);
        phases[0].words = stream;
        phases[0].faces = map.frame_faces;
        fx2.source(stream, 0, stream.size());
        // the top's power-up reset of its IFCLK side begins phase 0
    }
    uint64_t vp_cycles = 0, error_at = 0, done_at = 0, last_progress = 0;
    unsigned error_records = 0, results = 0, straddled = 0;
    bool error_seen = false, stop = false;

    auto model_open = [&](Phase &p) -> bool {
        alb_model_config c;
        alb_model_config_default(&c);
        c.producer = ALB_PRODUCER_EXTERNAL;
        c.events = ALB_EV_FRAME;
        c.name = o.stream;
        std::vector<const char *> ov(o.sets);
        ov.push_back(nullptr);
        alb_diag d;
        alb_diag_init(&d, nullptr);
        if (alb_model_open(&p.model, o.profile, ov.data(), &c, &d)) {
            std::fprintf(stderr, "top_bench: the model: %s\n", d.msg);
            return false;
        }
        return true;
    };

    // The VP's clock edge: the model takes the word the VP takes and steps a clock.
    auto vp_edge = [&]() -> bool {
        vp_cycles++;
        if (top->vp_rst) {
            if (vp_phase >= 0) {
                Phase &p = phases[(size_t)vp_phase];
                alb_model_destroy(p.model);
                p.model = nullptr;
                vp_phase = -1;
            }
            return true;
        }
        if (phases.empty() || restart_pending) {
            if (top->vp_take)
                f.fail("VP cycle %" PRIu64 ": the VP takes a word %08x before the stream's RESET",
                       (uint64_t)top->vp_cycle, top->vp_word);
            return !top->vp_take;
        }
        if (vp_phase < 0) {
            vp_phase = (int)phases.size() - 1;
            if (!error_case && !model_open(phases.back()))
                return false;
        }
        Phase &p = phases[(size_t)vp_phase];
        alb_model *m = p.model;
        const bool stepping = m && !alb_model_done(m);
        if (stepping && top->vp_cycle != alb_model_cycle(m)) {
            f.fail("phase %d: the VP's cycle counter reads %" PRIu64 ", the model's %" PRIu64,
                   vp_phase, (uint64_t)top->vp_cycle, alb_model_cycle(m));
            return false;
        }
        if (top->vp_take) {
            last_progress = vp_cycles;
            if (p.taken >= p.words.size()) {
                f.fail("phase %d, VP cycle %" PRIu64 ": the VP takes a word %08x after the "
                       "stream's %zu", vp_phase, (uint64_t)top->vp_cycle, top->vp_word,
                       p.words.size());
                return false;
            }
            if (top->vp_word != p.words[p.taken]) {
                f.fail("phase %d, VP cycle %" PRIu64 ": the VP takes %08x as word %zu, the "
                       "stream's word is %08x", vp_phase, (uint64_t)top->vp_cycle, top->vp_word,
                       p.taken, p.words[p.taken]);
                return false;
            }
            if (stepping && alb_model_push(m, &p.words[p.taken], 1) != 1) {
                f.fail("phase %d, VP cycle %" PRIu64 ": the VP's FIFO takes word %zu, the "
                       "model's cannot (%s)", vp_phase, (uint64_t)top->vp_cycle, p.taken,
                       alb_model_error(m));
                return false;
            }
            p.taken++;
        }
        if (stepping) {
            if (alb_model_step(m, 1)) {
                f.fail("phase %d: the model: %s", vp_phase, alb_model_error(m));
                return false;
            }
            alb_event ev;
            while (alb_model_event(m, &ev) == 1) {
                if (ev.kind != ALB_EV_FRAME)
                    continue;
                if (p.frames_retired >= p.faces.size()) {
                    f.fail("phase %d: the model retires more frames than the stream has", vp_phase);
                    return false;
                }
                p.owed.push_back({ev.number, ev.crc, (uint32_t)ev.cycles,
                                  (uint32_t)(ev.cycles >> 32), p.faces[p.frames_retired]});
                p.frames_retired++;
            }
        }
        if (top->vp_error && !error_seen) {
            error_seen = true;
            error_at = vp_cycles;
            if (!error_case)
                f.fail("phase %d, VP cycle %" PRIu64 ": the VP reports error %u at word %u",
                       vp_phase, (uint64_t)top->vp_cycle, top->vp_error_code, top->vp_error_word);
            else if (o.expect_code >= 0 && top->vp_error_code != (unsigned)o.expect_code)
                f.fail("the VP reports error %u, expected %d", top->vp_error_code, o.expect_code);
        }
        // a restart due: the 8051 acts at its next clock
        if (next_restart < o.restarts.size() && !restart_pending && !fx2.restarting()) {
            const Restart &r = o.restarts[next_restart];
            if (r.in_record < 0 && p.taken >= r.at) {
                restart_pending = true;
                restart_new = r.new_stream;
            }
        }
        return true;
    };

    // A record the 8051 took from EP8.
    auto record = [&](const Fx2::Packet &pk) {
        last_progress = vp_cycles;
        const size_t bytes = 2 * pk.beats.size();
        std::vector<uint32_t> u;
        for (size_t i = 0; i + 1 < pk.beats.size(); i += 2)
            u.push_back((uint32_t)pk.beats[i] | (uint32_t)pk.beats[i + 1] << 16);
        // a record begun before a VP_RESTART goes out whole after it (the
        // top's record path outlives a restart): it is the first beat's
        // phase's, and checked as such below
        if (pk.mixed)
            straddled++;
        if (bytes == 4) {
            error_records++;
            if (rec)
                std::fprintf(rec, "error %d %u\n", pk.phase, u[0]);
            if (!error_case)
                f.fail("an error record: word %u", u[0]);
            else if (u[0] != (uint64_t)o.expect_error)
                f.fail("the error record says word %u, expected %lld", u[0], o.expect_error);
            else if (error_records > 1)
                f.fail("a second error record");
            return;
        }
        if (bytes != 20) {
            f.fail("a record of %zu bytes (RESULT is 20, an error 4)", bytes);
            // the firmware rejects it (fw_vp_error ~0): it stood for the next frame owed
            if (!error_case && pk.phase >= 0 && (size_t)pk.phase < phases.size() &&
                !phases[(size_t)pk.phase].owed.empty()) {
                phases[(size_t)pk.phase].owed.pop_front();   // (not seen: a RESUME resends it)
            }
            return;
        }
        results++;
        Result got = {u[0], u[1], u[2], u[3], u[4]};
        if (rec)
            std::fprintf(rec, "result %d %u %08x %" PRIu64 " %u\n", pk.phase, got.frame, got.crc,
                         (uint64_t)got.cycles_hi << 32 | got.cycles_lo, got.faces);
        if (error_case) {
            f.fail("a RESULT record (frame %u) where the stream is refused", got.frame);
            return;
        }
        if (pk.phase < 0 || (size_t)pk.phase >= phases.size()) {
            f.fail("a RESULT of an unknown epoch %d", pk.phase);
            return;
        }
        Phase &p = phases[(size_t)pk.phase];
        if (p.owed.empty()) {
            f.fail("phase %d: a RESULT (frame %u, CRC %08x) the model has no frame for",
                   pk.phase, got.frame, got.crc);
            return;
        }
        const Result want = p.owed.front();
        p.owed.pop_front();
        p.results_seen++;
        static const char *const names[5] = {"frame", "CRC", "cycles low", "cycles high", "faces"};
        const uint32_t *g = &got.frame, *w = &want.frame;
        for (int k = 0; k < 5; k++)
            if (g[k] != w[k])
                f.fail("phase %d, RESULT of frame %u: u32 %d (%s) is %08x, the model's %08x",
                       pk.phase, want.frame, k, names[k], g[k], w[k]);
        if (!o.quiet)
            std::printf("top_bench: phase %d frame %u: CRC %08x, %" PRIu64 " cycles, %u faces%s\n",
                        pk.phase, got.frame, got.crc,
                        (uint64_t)got.cycles_hi << 32 | got.cycles_lo, got.faces,
                        std::memcmp(&got, &want, sizeof got) ? "  MISMATCH" : "");
    };

    // The 8051's restart: RESUME from the first frame of the stream whose
    // RESULT it has not seen (as the host does), or RESET to the stream's start.
    auto do_restart = [&]() {
        const bool initial = phases.empty();
        Phase none;
        Phase &old = initial ? none : phases.back();
        Phase np;
        if (restart_new) {
            np.words = stream;
            np.faces = map.frame_faces;
            np.first_frame = 0;
            fx2.source(stream, 0, stream.size());
        } else {
            size_t from = old.first_frame + old.results_seen;
            size_t at = from < map.frame_at.size() ? map.frame_at[from] : map.end_at;
            np.words.assign(stream.begin(), stream.begin() + 3);   // the CONFIG the top keeps
            np.words.insert(np.words.end(), stream.begin() + (long)at, stream.end());
            np.faces.assign(map.frame_faces.begin() + (long)std::min(from, map.frame_faces.size()),
                            map.frame_faces.end());
            np.first_frame = from;
            fx2.source(stream, at, stream.size());
        }
        if (!o.quiet && !initial)
            std::printf("top_bench: %s after %zu words of phase %zu (RESULTs of %zu frames seen); "
                        "phase %zu starts at frame %zu\n", restart_new ? "RESET" : "RESUME",
                        old.taken, phases.size() - 1, old.results_seen, phases.size(),
                        np.first_frame);
        phases.push_back(std::move(np));
        fx2.restart(restart_new);
        if (!initial)
            next_restart++;    // the initial RESET is no --resume or --reset
        restart_pending = false;
    };

    // ---- the clocks: two unrelated periods, IFCLK's first edge phase_ps late ----
    const uint64_t vp_per = period_ps(o.vp_khz), if_per = period_ps(o.if_khz);
    uint64_t vp_next = vp_per, if_next = o.phase_ps % if_per + if_per;
    top->clk_vp = 0;
    top->ifclk = 0;
    fx2.drive(*top);
    top->eval();
    uint64_t now_ps = 0;
    while (!stop) {
        now_ps = std::min(vp_next, if_next);
        const bool vp = vp_next == now_ps, ifc = if_next == now_ps;
        if (vp && !vp_edge())
            break;
        if (ifc) {
            if (top->rst_if && !rst_if_was)
                fpga_phase++;
            rst_if_was = top->rst_if;
            if (restart_pending)
                do_restart();
            // --restart-in-record K: in the middle of a record's beats
            if (next_restart < o.restarts.size() && o.restarts[next_restart].in_record >= 0 &&
                !fx2.restarting() && fx2.ep8_fill_beats() == (size_t)o.restarts[next_restart].in_record) {
                restart_new = false;
                do_restart();
            }
            fx2.sample(*top, fpga_phase);
        }
        top->clk_vp = vp;
        top->ifclk = ifc;
        top->eval();
        if (tfp)
            tfp->dump(now_ps);
        if (ifc) {
            fx2.drive(*top);
            Fx2::Packet pk;
            while (fx2.take(pk))
                record(pk);
        }
        top->clk_vp = 0;
        top->ifclk = 0;
        top->eval();
        if (ifc)
            fx2.check_bus(*top);
        if (tfp)
            tfp->dump(now_ps + 1);
        if (vp)
            vp_next += vp_per;
        if (ifc)
            if_next += if_per;

        // the end: everything sent, taken, retired and reported
        if (vp && !phases.empty()) {
            Phase &p = phases.back();
            bool finished;
            if (error_case)
                finished = error_records > 0;
            else
                finished = next_restart == o.restarts.size() && !restart_pending &&
                           !fx2.restarting() && vp_phase == (int)phases.size() - 1 && p.model &&
                           alb_model_done(p.model) && p.owed.empty() && fx2.source_done() &&
                           fx2.ep8_idle();
            if (finished && !done_at)
                done_at = vp_cycles;
            if (done_at && vp_cycles >= done_at + 4000)
                stop = true;   // time for a record nobody expected to show
            const bool stuck = vp_cycles - last_progress > 400000;
            if (stuck || vp_cycles >= o.max_cycles) {
                char why[64];
                if (stuck)
                    std::snprintf(why, sizeof why, "nothing for 400000 VP cycles");
                else
                    std::snprintf(why, sizeof why, "--max-cycles %" PRIu64 " reached", o.max_cycles);
                if (error_case)
                    f.fail("%s: no error record (the VP %s)", why,
                           error_seen ? "reported its error" : "reported no error");
                else
                    f.fail("%s: %zu of %zu words taken, %zu RESULTs owed, the model %s", why,
                           p.taken, p.words.size(), p.owed.size(),
                           p.model && alb_model_done(p.model) ? "done" : "not done");
                stop = true;
            }
        }
    }
    (void)error_at;
    if (!error_case && !(top->led & 1))   // LED_LOW 1: lit when low
        f.fail("the error LED is lit (an error, a memory conflict or a lost record)");
    if (error_case && !error_seen)
        f.fail("the VP reported no error");
    for (size_t i = 0; i < phases.size(); i++)
        if (!phases[i].owed.empty() && i + 1 == phases.size())
            f.fail("phase %zu: %zu RESULTs never came (first: frame %u)", i,
                   phases[i].owed.size(), phases[i].owed.front().frame);
    size_t lost_at_restart = 0;
    for (size_t i = 0; i + 1 < phases.size(); i++)
        lost_at_restart += phases[i].owed.size();
    top->final();
    if (tfp)
        tfp->close();
    for (Phase &p : phases)
        alb_model_destroy(p.model);
    if (rec && std::fclose(rec)) {
        std::fprintf(stderr, "top_bench: %s: write error\n", o.records);
        return 2;
    }
    std::printf("top_bench: %" PRIu64 " VP cycles at %.0f kHz, %" PRIu64 " IFCLKs at %.0f kHz "
                "(%.3f ms); %" PRIu64 " beats read, %u RESULTs, %u error records, %zu phases "
                "(%zu RESULTs dropped by restarts, %u records across one); EP8 full %" PRIu64
                " times (%" PRIu64 " IFCLKs); %s\n", vp_cycles, o.vp_khz, fx2.now(), o.if_khz,
                (double)now_ps / 1e9, fx2.beats_read(), results, error_records, phases.size(),
                lost_at_restart, straddled,
                fx2.full_episodes(), fx2.full_clocks(), f.count ? "FAILED" : "ok");
    return f.count ? 1 : 0;
}

}   // namespace

int main(int argc, char **argv)
{
    Options o = parse(argc, argv);
    return run(o);
}
