# albatros — the front door: make, make test, make asan, make bench, make demo.
# GNU Make; dependencies through pkg-config; make help lists the targets.

.DEFAULT_GOAL := all

CC      ?= cc
# the library's version: ALB_ABI is the SONAME's, raised on any incompatible
# change of include/albatros/ (include/albatros/albatros.h has the same numbers)
ALB_ABI   := 0
ALB_MINOR := 1
ALB_PATCH := 0
BUILD   ?= build
PKGS    := libpng libusb-1.0 hidapi-hidraw zlib
# OpenEXR 3.1 has no pkg-config module for its C library alone: the C API
# (OpenEXRCore) takes the OpenEXR module's include path and one library.
EXR_CFLAGS := $(shell pkg-config --cflags OpenEXR)
EXR_LIBS   := -lOpenEXRCore-3_1
OPT     ?= -O2
WARN    := -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
           -Wpointer-arith -Wcast-qual -Wvla
# The GP's doubles must round the same everywhere: no contraction into fused
# multiply-adds, no fast-math (docs/number-formats.md).
FPFLAGS := -ffp-contract=off -fno-fast-math
CFLAGS  ?= $(OPT) -g
ALL_CFLAGS = -std=c11 -D_POSIX_C_SOURCE=200809L -pthread -Iinclude $(WARN) $(FPFLAGS) $(CFLAGS) $(EXTRA_CFLAGS) \
             $(shell pkg-config --cflags $(PKGS)) $(EXR_CFLAGS)
LDLIBS  = $(shell pkg-config --libs $(PKGS)) $(EXR_LIBS) -lm -pthread $(EXTRA_LDLIBS)

COMMON_SRC := common/diag.c common/file.c common/json.c common/memh.c common/profile.c common/words.c \
              common/crmath.c
GP_SRC     := gp/scene.c gp/texture.c gp/obj.c gp/quant.c gp/bound.c gp/polygon.c gp/gp.c gp/builtin.c
VP_SRC     := vp/vp.c vp/fill.c vp/store.c vp/parallel.c vp/shade.c vp/frame.c
SINK_SRC   := emu/exr.c emu/preview.c emu/sim.c emu/sim_timed.c emu/sim_cycle.c emu/vcd.c \
              emu/model.c emu/dpi.c emu/dump.c emu/frame_out.c
BRIDGE_SRC := emu/bridge/link.c emu/bridge/stream.c emu/bridge/transport_fault.c \
              emu/bridge/transport_usb.c
TOOLS_SRC  := tools/ref.c tools/scenegen.c tools/accuracy.c tools/stress.c tools/methods.c tools/sweep.c \
              $(wildcard tools/methods/*.c)
FW_SRC     := firmware/core.c firmware/crc32.c firmware/sim/board.c firmware/sim/transport.c \
              firmware/sim/rtl_load.c
EMU_SRC    := emu/main.c emu/cmd_gp.c emu/cmd_vectors.c emu/cmd_render.c emu/cmd_compare.c emu/cmd_scene.c emu/cmd_stream.c emu/cmd_stability.c \
              emu/cli.c
TEST_SRC   := $(wildcard tests/test_*.c) tests/t.c tests/gp_helpers.c tests/refpacket.c

# ---- libalbatros (docs/architecture.md): common, GP, VP, the timed and
# cycle models, the sinks and the bridge host.  Its objects are position
# independent and hide every symbol the public headers (include/albatros/)
# do not declare; the shared library exports alb_* alone (lib/albatros.map)
# and the static one is one relocatable object with everything else made
# local, so a testbench linking it meets no generic name.
LIBALB_SRC := $(COMMON_SRC) $(GP_SRC) $(VP_SRC) $(SINK_SRC) $(BRIDGE_SRC)
LIBALB_OBJ := $(patsubst %.c,$(BUILD)/%.o,$(LIBALB_SRC)) $(BUILD)/gen/builtin_scene.o
LIB_SONAME := libalbatros.so.$(ALB_ABI)
LIBALB_A   := $(BUILD)/lib/libalbatros.a
LIBALB_SO  := $(BUILD)/lib/libalbatros.so.$(ALB_ABI).$(ALB_MINOR).$(ALB_PATCH)
LIB_CFLAGS := -fPIC -fvisibility=hidden
# (a target-specific variable of its own: EXTRA_CFLAGS on the command line,
# as CI and make asan give it, would override one added to EXTRA_CFLAGS)
$(LIBALB_OBJ): OBJ_CFLAGS := $(LIB_CFLAGS)

# What the albatros command adds to the library: the CLI, the references,
# classic methods and stress scenes (tools/), and the simulated board with
# the firmware core (firmware/sim/).  The command links the static library,
# so it can use the public API only.
CLIENT_OBJ := $(patsubst %.c,$(BUILD)/%.o,$(TOOLS_SRC) $(FW_SRC))
# The tools' generated scenes use the GP's correctly rounded maths
# (common/crmath.c), which the static library keeps to itself: linked again.
CLIENT_OBJ += $(BUILD)/common/crmath.o
EMU_OBJ    := $(patsubst %.c,$(BUILD)/%.o,$(EMU_SRC))
TEST_OBJ   := $(patsubst %.c,$(BUILD)/%.o,$(TEST_SRC))
# tests, fuzz harnesses and benchmarks reach inside the units: every object
LIB_OBJ    := $(sort $(LIBALB_OBJ) $(CLIENT_OBJ))

ALBATROS := $(BUILD)/albatros
DPI_TB   := $(BUILD)/dpi/tb_vector
UNIT     := $(BUILD)/tests/unit
USB_DESC := $(BUILD)/tests/usb_descriptors
# the board on an emulated USB bus (umockdev) and its permission shim
USB_BOARD := $(BUILD)/tests/usb_board
USB_SHIM  := $(BUILD)/tests/usb_access.so
USB_ROGUE := $(BUILD)/tests/usb_rogue
USB_BENCH := $(BUILD)/tests/usb_bench
UMOCKDEV_CFLAGS = $(shell pkg-config --cflags umockdev-1.0)
UMOCKDEV_LIBS   = $(shell pkg-config --libs umockdev-1.0)

# the FX2LP firmware (sdcc): make firmware, make firmware-size
include firmware/fx2/fx2.mk

COST     := $(BUILD)/tools/cost
BENCH    := $(BUILD)/tools/bench
BENCH_MODEL := $(BUILD)/tools/bench-model

.PHONY: all test unit vectors bless asan tsan memcheck bench demo setup deps clean help crosscheck sweep \
        usb-bench
# libFuzzer harnesses and their replay over the seeds and regressions
include fuzz/fuzz.mk
# the reference RTL and its co-simulation against the model: make cosim
include rtl/rtl.mk
include rtl/fpga/fpga.mk

# the replay harnesses too, so a warning in them fails CI's -Werror build
all: $(ALBATROS) $(LIBALB_SO) $(UNIT) $(USB_DESC) $(USB_BOARD) $(USB_SHIM) $(USB_ROGUE) $(USB_BENCH) $(REPLAYS) $(DPI_TB)

help:
	@echo "make            build $(ALBATROS) and the tests"
	@echo "make setup      install missing Debian packages (apt-get), then build"
	@echo "make demo       run the main job on the built-in scene (out/)"
	@echo "make test       run every test (unit, CLI, golden vectors)"
	@echo "make vectors    check the golden vectors only"
	@echo "make bless      regenerate the golden vectors' expected outputs"
	@echo "make asan       build and test under AddressSanitizer + UBSan"
	@echo "make tsan       the unit tests under ThreadSanitizer (the worker threads)"
	@echo "make memcheck   the tests under valgrind memcheck (slow)"
	@echo "make bench      print speed and work figures (docs/performance.md)"
	@echo "make usb-bench  USB bulk throughput through libusb on the emulated bus"
	@echo "make crosscheck the golden vectors from gcc -O0, clang -O3 and musl-gcc builds"
	@echo "make -j sweep   the stability and speed sweeps, report in docs/stability/"
	@echo "make fuzz-TARGET [FUZZ_TIME=600]  fuzz one input path (clang + libFuzzer):"
	@echo "                TARGET = $(FUZZ_TARGETS) (fuzz/README.md)"
	@echo "make fuzz-replay  the fuzz harnesses over their seeds and regressions (in make test)"
	@echo "make firmware   the FX2LP board firmware (sdcc); make firmware-size checks it fits"
	@echo "make firmware-check  that image on the s51 simulator against the host core (in make test)"
	@echo "make firmware-speed  its parsing speed on the bridge's stream, from s51's cycle counts"
	@echo "make cosim      the reference RTL (rtl/) against the cycle model, everything (rtl/README.md)"
	@echo "make fpga       the VP for an iCE40 HX8K board: bitstream and nextpnr report (docs/fpga.md)"
	@echo "make fpga-check make fpga, then: does it fit and meet its clock"
	@echo "make fpga-top   the FPGA top simulated with the FX2's side, and its planted bugs (rtl/fpga/README.md)"
	@echo "make -j2 fpga-sweep  the design-space view: cells per unit against cycles per frame (docs/fpga.md)"
	@echo "make clean"

# ---- set-up: install what pkg-config cannot find (Debian 12) ----
DEB_PKGS := build-essential pkg-config libpng-dev zlib1g-dev libopenexr-dev openexr libusb-1.0-0-dev \
            libhidapi-dev gnuplot-nox sdcc sdcc-ucsim umockdev libumockdev-dev verilator iverilog yosys nextpnr-ice40 fpga-icestorm python3 man-db \
            musl-tools valgrind openimageio-tools libosmesa6-dev
setup: deps
	$(MAKE) all
deps:
	@missing=""; \
	for p in $(DEB_PKGS); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update && $$SUDO apt-get install -y $$missing; \
	else echo "all build dependencies present"; fi

# ---- build ----
# The compiler and its flags as last used in $(BUILD): rewritten when they
# change, and every object depends on it, so a build with other flags
# (EXTRA_CFLAGS=-Werror, CC=clang, OPT=-O0) never links objects of the last.
FLAGS_STAMP := $(BUILD)/.flags
FLAGS_NOW    = $(CC) $(ALL_CFLAGS) | $(LIB_CFLAGS)
ifeq ($(filter clean help,$(MAKECMDGOALS)),)
$(shell mkdir -p $(BUILD) && printf '%s\n' '$(subst ','\'',$(FLAGS_NOW))' > $(FLAGS_STAMP).new && \
  { cmp -s $(FLAGS_STAMP).new $(FLAGS_STAMP) && rm -f $(FLAGS_STAMP).new || mv -f $(FLAGS_STAMP).new $(FLAGS_STAMP); })
endif

$(BUILD)/%.o: %.c $(FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(OBJ_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/gen/%.o: $(BUILD)/gen/%.c $(FLAGS_STAMP)
	$(CC) $(ALL_CFLAGS) $(OBJ_CFLAGS) -I. -c $< -o $@

$(BUILD)/tools/embed: tools/embed.c
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(WARN) -O1 $< -o $@

$(BUILD)/gen/builtin_scene.c: gp/builtin.scene $(BUILD)/tools/embed
	@mkdir -p $(dir $@)
	$(BUILD)/tools/embed scene_builtin_data $< $@

$(LIBALB_A): $(LIBALB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ $(BUILD)/lib/albatros.o
	$(LD) -r -o $(BUILD)/lib/albatros.o $^
	objcopy --localize-hidden $(BUILD)/lib/albatros.o
	$(AR) rcsD $@ $(BUILD)/lib/albatros.o

$(LIBALB_SO): $(LIBALB_OBJ) lib/albatros.map
	@mkdir -p $(dir $@)
	$(CC) -shared -Wl,-soname,$(LIB_SONAME) -Wl,--version-script=lib/albatros.map -Wl,-z,defs \
	  $(LIBALB_OBJ) $(LDLIBS) -o $@
	ln -sf $(notdir $@) $(BUILD)/lib/$(LIB_SONAME)
	ln -sf $(LIB_SONAME) $(BUILD)/lib/libalbatros.so

# a SystemVerilog bench over DPI-C, built by Verilator against the shared
# library (tests/dpi.sh)
$(DPI_TB): include/albatros/albatros_pkg.sv tests/dpi/tb_vector.sv $(LIBALB_SO)
	@mkdir -p $(BUILD)/dpi
	+verilator --binary -j 2 -Wall --Mdir $(BUILD)/dpi/obj --top-module tb_vector \
	  include/albatros/albatros_pkg.sv tests/dpi/tb_vector.sv \
	  -LDFLAGS "-L$(abspath $(BUILD)/lib) -lalbatros -Wl,-rpath,$(abspath $(BUILD)/lib) $(EXTRA_LDLIBS)" \
	  -o tb_vector
	cp $(BUILD)/dpi/obj/tb_vector $@

$(ALBATROS): $(EMU_OBJ) $(CLIENT_OBJ) $(LIBALB_A)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

$(COST): $(BUILD)/tools/cost.o $(LIB_OBJ)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

# the bench's peer, Mesa's llvmpipe through OSMesa (tools/peer.c), links
# into the bench alone
$(BENCH): $(BUILD)/tools/bench.o $(BUILD)/tools/peer.o $(LIB_OBJ)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) $(shell pkg-config --libs osmesa) -o $@

# a client of the public API alone: the static library
$(BENCH_MODEL): $(BUILD)/tools/bench_model.o $(LIBALB_A)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@


# the FX2 firmware's descriptors, on the host, for tests/usb-umockdev.sh
$(USB_DESC): tests/usb_descriptors.c firmware/fx2/descriptors.c firmware/fx2/usb.h firmware/proto.h
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -D__xdata= tests/usb_descriptors.c firmware/fx2/descriptors.c -o $@ $(EXTRA_LDLIBS)

# umockdev's API is GObject: the board links glib, nothing else does
$(USB_BOARD): tests/usb_board.c firmware/fx2/descriptors.c firmware/fx2/usb.h $(LIB_OBJ)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(UMOCKDEV_CFLAGS) -D__xdata= tests/usb_board.c firmware/fx2/descriptors.c \
	  $(LIB_OBJ) $(LDLIBS) $(UMOCKDEV_LIBS) -o $@

# a host that breaks the board's rules on purpose: each check of usb_board fires
$(USB_ROGUE): tests/usb_rogue.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $< -o $@ $(shell pkg-config --libs libusb-1.0) $(EXTRA_LDLIBS)

# bulk throughput through libusb, a client of the public API (make usb-bench)
$(USB_BENCH): $(BUILD)/tests/usb_bench.o $(LIBALB_A)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

# preloaded into any program, sanitized or not: built without the sanitizers
$(USB_SHIM): tests/usb_access.c
	@mkdir -p $(dir $@)
	$(CC) -std=c11 $(WARN) $(CFLAGS) $(filter-out -fsanitize%,$(EXTRA_CFLAGS)) -fPIC -shared $< -o $@ -ldl

$(UNIT): $(TEST_OBJ) $(LIB_OBJ)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

# ---- tests: every runner prints "N passed, N failed"; tests/summary adds them ----
test: all
	@bash tests/run-all.sh $(BUILD)

unit: $(UNIT)
	$(UNIT)

vectors: $(ALBATROS)
	$(ALBATROS) vectors check test-vectors

bless: $(ALBATROS)
	$(ALBATROS) vectors bless test-vectors

# the unit, CLI, vector and malformed-input runners under valgrind memcheck:
# errors and definite/indirect leaks fail (slow: not part of make test)
memcheck: $(ALBATROS) $(UNIT)
	@bash tests/run-all.sh $(BUILD) --memcheck

# float-cast-overflow: gcc's -fsanitize=undefined leaves it out
asan:
	$(MAKE) BUILD=build-asan OPT=-O1 \
	  EXTRA_CFLAGS="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer" \
	  EXTRA_LDLIBS="-fsanitize=address,undefined,float-cast-overflow" test

# the unit tests under ThreadSanitizer: the worker threads' tasks, shares
# and batches (vp/parallel.c; tests/test_threads.c, and every thread count
# against one in tests/test_timing.c); any report fails the run
tsan:
	$(MAKE) BUILD=build-tsan OPT=-O1 EXTRA_CFLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
	  EXTRA_LDLIBS="-fsanitize=thread" build-tsan/tests/unit
	TSAN_OPTIONS="halt_on_error=1 exitcode=66" build-tsan/tests/unit

# bit-exact across compilers, optimisation and C libraries: every golden
# vector (streams, frames, counters) from gcc -O0 and clang -O3 builds, and
# from a musl-gcc build (a second C library: its libm must change nothing,
# docs/number-formats.md §0); the gcc one takes the VP's plain C paths where
# the others have SIMD (vp/simd.h)
crosscheck: $(ALBATROS)
	$(MAKE) BUILD=build-gcc-O0 OPT=-O0 EXTRA_CFLAGS=-DALB_NO_SIMD build-gcc-O0/albatros
	$(MAKE) BUILD=build-clang-O3 CC=clang OPT=-O3 build-clang-O3/albatros
	build-gcc-O0/albatros vectors check test-vectors
	build-clang-O3/albatros vectors check test-vectors
	$(MAKE) $(MUSL_ALBATROS)
	$(ALBATROS) vectors digest test-vectors > $(MUSL_BUILD)/expected.digests
	$(MUSL_ALBATROS) vectors check --digests $(MUSL_BUILD)/expected.digests test-vectors

# The musl build: musl-gcc cannot link the glibc-built libpng, libusb,
# hidapi and OpenEXR, so ALB_NO_EXTERNAL leaves out what needs them (EXR and
# PNG output, PNG textures, USB; render, stream and the tools): an albatros
# with gp, dump, profiles and vectors check --digests, which compares the
# frames by the digests the full build reads from the expected EXR files
# (docs/golden-vectors.md, "Another C library").
MUSL_CC       ?= musl-gcc
MUSL_BUILD    := build-musl
MUSL_ALBATROS := $(MUSL_BUILD)/albatros
MUSL_SRC      := $(COMMON_SRC) $(GP_SRC) $(VP_SRC) emu/sim.c emu/sim_timed.c emu/sim_cycle.c \
                 emu/vcd.c emu/model.c emu/frame_out.c emu/bridge/link.c firmware/crc32.c \
                 emu/main.c emu/cli.c emu/cmd_gp.c emu/cmd_vectors.c
MUSL_OBJ      := $(patsubst %.c,$(MUSL_BUILD)/%.o,$(MUSL_SRC)) $(MUSL_BUILD)/gen/builtin_scene.o
MUSL_CFLAGS   := -std=c11 -D_POSIX_C_SOURCE=200809L -DALB_NO_EXTERNAL -pthread -Iinclude $(WARN) \
                 $(FPFLAGS) -O2 $(EXTRA_CFLAGS)
$(MUSL_BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(MUSL_CC) $(MUSL_CFLAGS) -MMD -MP -c $< -o $@
$(MUSL_BUILD)/gen/builtin_scene.o: $(BUILD)/gen/builtin_scene.c
	@mkdir -p $(dir $@)
	$(MUSL_CC) $(MUSL_CFLAGS) -I. -c $< -o $@
$(MUSL_ALBATROS): $(MUSL_OBJ)
	$(MUSL_CC) $(MUSL_CFLAGS) $^ -lm -pthread -o $@
-include $(shell find $(MUSL_BUILD) -name '*.d' 2>/dev/null)

# the stability sweep: one job per stress family (make -j runs them in
# parallel), the speed sweep alone after them (its timings), then the report;
# docs/stability/ holds the committed default sweep (docs/stability.md).
# Every make sweep reruns every job (sweep-always): the committed CSVs are
# results, not sources that make could call up to date.
SWEEP_DIR ?= docs/stability
SWEEP_FAMILIES := sliver crossing-z0 far texture-far interpenetrating cyclic degenerate \
                  tjunction deep coords
SWEEP_CSV := $(SWEEP_FAMILIES:%=$(SWEEP_DIR)/stability-%.csv)
.PHONY: sweep-always
sweep: $(SWEEP_CSV) $(SWEEP_DIR)/speed.csv
	$(ALBATROS) stability --report --out $(SWEEP_DIR)
$(SWEEP_DIR)/stability-%.csv: $(ALBATROS) sweep-always
	@mkdir -p $(SWEEP_DIR)
	$(ALBATROS) stability --family $* --out $(SWEEP_DIR)
$(SWEEP_DIR)/speed.csv: $(SWEEP_CSV) $(ALBATROS) sweep-always
	$(ALBATROS) stability --speed --out $(SWEEP_DIR)

# figures, not tests: docs/performance.md quotes them
bench: $(COST) $(BENCH) $(BENCH_MODEL)
	$(BENCH)
	$(BENCH_MODEL)
	$(COST)

# MB/s through libusb against transfers in flight and their size, on the
# emulated bus (docs/usb-protocol.md, "Throughput"); about two minutes
usb-bench: $(USB_BOARD) $(USB_SHIM) $(USB_BENCH)
	@bash tests/usb-bench.sh $(BUILD)

# ---- install (docs/architecture.md, "Installed") ----
PREFIX     ?= /usr/local
BINDIR     ?= $(PREFIX)/bin
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
DATADIR    ?= $(PREFIX)/share
MANDIR     ?= $(DATADIR)/man
DOCDIR     ?= $(DATADIR)/doc/albatros
COMPDIR    ?= $(DATADIR)/bash-completion/completions
UDEVDIR    ?= $(PREFIX)/lib/udev/rules.d
# Debian's python3 reads /usr/lib/python3/dist-packages and, for local
# installs, /usr/local/lib/python3.X/dist-packages
PYVER      := $(shell python3 -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)
PYTHONDIR  ?= $(if $(filter /usr,$(PREFIX)),$(PREFIX)/lib/python3/dist-packages,$(PREFIX)/lib/python$(PYVER)/dist-packages)
INSTALL    ?= install
PUBLIC_H   := $(wildcard include/albatros/*.h) include/albatros/albatros_pkg.sv
DOCS       := $(wildcard docs/*.md)
SO_LINKS   := $(LIB_SONAME) libalbatros.so

$(BUILD)/albatros.pc: lib/albatros.pc.in Makefile
	sed -e 's|@PREFIX@|$(PREFIX)|; s|@LIBDIR@|$(LIBDIR)|; s|@INCLUDEDIR@|$(INCLUDEDIR)|' \
	    -e 's|@VERSION@|$(ALB_ABI).$(ALB_MINOR).$(ALB_PATCH)|' $< > $@.tmp && mv $@.tmp $@

.PHONY: install uninstall $(BUILD)/albatros.pc
install: $(ALBATROS) $(LIBALB_SO) $(LIBALB_A) $(BUILD)/albatros.pc
	$(INSTALL) -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCLUDEDIR)/albatros \
	    $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(DOCDIR) $(DESTDIR)$(COMPDIR) $(DESTDIR)$(UDEVDIR) \
	    $(DESTDIR)$(PYTHONDIR)
	$(INSTALL) -m 755 $(ALBATROS) $(DESTDIR)$(BINDIR)/albatros
	$(INSTALL) -m 755 $(LIBALB_SO) $(DESTDIR)$(LIBDIR)/
	$(INSTALL) -m 644 $(LIBALB_A) $(DESTDIR)$(LIBDIR)/
	ln -sf $(notdir $(LIBALB_SO)) $(DESTDIR)$(LIBDIR)/$(LIB_SONAME)
	ln -sf $(LIB_SONAME) $(DESTDIR)$(LIBDIR)/libalbatros.so
	$(INSTALL) -m 644 $(BUILD)/albatros.pc $(DESTDIR)$(LIBDIR)/pkgconfig/albatros.pc
	$(INSTALL) -m 644 $(PUBLIC_H) $(DESTDIR)$(INCLUDEDIR)/albatros/
	$(INSTALL) -m 644 docs/albatros.1 $(DESTDIR)$(MANDIR)/man1/albatros.1
	$(INSTALL) -m 644 $(DOCS) examples/replay.c $(DESTDIR)$(DOCDIR)/
	$(INSTALL) -m 644 completions/albatros.bash $(DESTDIR)$(COMPDIR)/albatros
	$(INSTALL) -m 644 firmware/udev/70-albatros.rules $(DESTDIR)$(UDEVDIR)/
	$(INSTALL) -m 644 python/albatros.py $(DESTDIR)$(PYTHONDIR)/albatros.py

# removes what install put there, nothing else (and the directories only it
# made: include/albatros, doc/albatros)
uninstall:
	rm -f $(DESTDIR)$(BINDIR)/albatros $(DESTDIR)$(LIBDIR)/$(notdir $(LIBALB_SO)) \
	    $(addprefix $(DESTDIR)$(LIBDIR)/,$(SO_LINKS) libalbatros.a pkgconfig/albatros.pc) \
	    $(addprefix $(DESTDIR)$(INCLUDEDIR)/albatros/,$(notdir $(PUBLIC_H))) \
	    $(DESTDIR)$(MANDIR)/man1/albatros.1 $(addprefix $(DESTDIR)$(DOCDIR)/,$(notdir $(DOCS)) replay.c) \
	    $(DESTDIR)$(COMPDIR)/albatros $(DESTDIR)$(UDEVDIR)/70-albatros.rules \
	    $(DESTDIR)$(PYTHONDIR)/albatros.py
	-rmdir $(DESTDIR)$(INCLUDEDIR)/albatros $(DESTDIR)$(DOCDIR) 2>/dev/null

demo: $(ALBATROS)
	@mkdir -p out
	$(ALBATROS) render -o out/builtin.exr --png out/builtin.png --stream out/builtin.stream

clean:
	rm -rf $(BUILD) $(FUZZ_BUILD) build-asan build-gcc-O0 build-clang-O3 build-clang build-musl out vector-diffs

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
