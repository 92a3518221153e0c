# firmware/fx2/fx2.mk — the FX2LP firmware, built by sdcc (Debian: sdcc).
# The top Makefile includes it after BUILD is set:
#
#   include firmware/fx2/fx2.mk
#
#   make firmware        $(BUILD)/firmware/albatros-fx2.ihx, with .map and .mem
#   make firmware-size   code and external data against the chip's 16 KB
#
# Memory (CY7C68013A): code and xdata share 16 KB of on-chip RAM at
# 0x0000-0x3FFF, which the host loads (fxload) or the boot EEPROM fills.
# Code is linked at 0x0000 and may grow to 0x3D00; xdata sits above it,
# 0x3D00-0x3FFF (768 bytes; the core's state is ~490 of them), so the linker
# refuses a build where either would overlap the other.  The reassembly
# buffer lives in the separate 512-byte scratch RAM at 0xE000 (main.c).
# --stack-auto: the core calls its HAL through function pointers with
# several arguments, which sdcc only allows for reentrant (stack-argument)
# functions; the stack is in the 256-byte internal RAM (--iram-size 256).

SDCC        ?= sdcc
FX2_OUT     := $(BUILD)/firmware
FX2_IHX     := $(FX2_OUT)/albatros-fx2.ihx
FX2_CODE    := 0x3d00
FX2_CFLAGS  := -mmcs51 --model-small --stack-auto --std-c99 --opt-code-size --Werror
FX2_LDFLAGS := --code-loc 0x0000 --code-size $(FX2_CODE) \
               --xram-loc $(FX2_CODE) --xram-size 0x0300 --iram-size 256
FX2_HDRS    := firmware/proto.h firmware/core.h firmware/fx2/usb.h firmware/fx2/fx2regs.h firmware/fx2/board.h
# main.rel first: sdcc links the module holding main() first
FX2_REL     := $(addprefix $(FX2_OUT)/,main.rel usb.rel descriptors.rel core.rel crc32.rel)

.PHONY: firmware firmware-size
firmware: $(FX2_IHX)

$(FX2_OUT)/%.rel: firmware/fx2/%.c $(FX2_HDRS)
	@mkdir -p $(FX2_OUT)
	$(SDCC) $(FX2_CFLAGS) -c $< -o $@

$(FX2_OUT)/%.rel: firmware/%.c firmware/proto.h firmware/core.h
	@mkdir -p $(FX2_OUT)
	$(SDCC) $(FX2_CFLAGS) -c $< -o $@

$(FX2_IHX): $(FX2_REL)
	$(SDCC) $(FX2_CFLAGS) $(FX2_LDFLAGS) $(FX2_REL) -o $@

# Code from the .ihx (its highest address), xdata from the linker's .mem:
# together they must fit the 16 KB.
firmware-size: $(FX2_IHX)
	@awk 'function hex(s,  i, v) { v = 0; for (i = 1; i <= length(s); i++) \
	        v = v * 16 + index("0123456789ABCDEF", toupper(substr(s, i, 1))) - 1; return v } \
	      FNR == NR { if (substr($$0, 8, 2) == "00") { e = hex(substr($$0, 4, 4)) + hex(substr($$0, 2, 2)); \
	                  if (e > code) code = e }; next } \
	      /^ *EXTERNAL RAM/ { xdata = $$5 } \
	      END { printf "code %d bytes (0x0000-0x%04X), xdata %d bytes, total %d of 16384\n", \
	                   code, code - 1, xdata, code + xdata; exit (code + xdata > 16384) }' \
	    $(FX2_IHX) $(FX2_OUT)/albatros-fx2.mem

# ---- the image on the s51 simulator (Debian: sdcc-ucsim), firmware/fx2/test/ ----
#
#   make firmware-check  the image against the host build of the core (in make test)
#   make firmware-speed  its parsing speed on the bridge's stream of the built-in
#                        scene, counted by s51 (docs/usb-protocol.md)
#
# fx2_s51 is a host program: it drives s51 and plays the chip's USB side and
# FPGA bus; the image it runs is the production one, unchanged.
FX2_S51     := $(BUILD)/firmware/fx2/test/fx2_s51
FX2_S51_SRC := $(addprefix firmware/fx2/test/,s51.c i8051.c listing.c fx2sim.c speed.c)
FX2_S51_OBJ := $(patsubst %.c,$(BUILD)/%.o,$(FX2_S51_SRC)) \
               $(BUILD)/firmware/fx2/test/fx2_s51.o $(BUILD)/firmware/fx2/test/descriptors_host.o \
               $(BUILD)/tests/refpacket.o
FX2_FASTPOLL := $(BUILD)/firmware/fx2/test/s51_fastpoll.so
FX2_SPEED_STREAM := $(FX2_OUT)/s51/builtin.stream
FX2_FPS     ?= 50

.PHONY: firmware-check firmware-speed
all: $(FX2_S51) $(FX2_FASTPOLL)
test memcheck: $(FX2_S51) $(FX2_FASTPOLL)

# the FX2 headers' memory qualifier means nothing on the host
$(BUILD)/firmware/fx2/test/fx2_s51.o: firmware/fx2/test/fx2_s51.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -D__xdata= -MMD -MP -c $< -o $@
$(BUILD)/firmware/fx2/test/descriptors_host.o: firmware/fx2/descriptors.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -D__xdata= -MMD -MP -c $< -o $@

$(FX2_S51): $(FX2_S51_OBJ) $(LIB_OBJ)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

# preloaded into s51, so none of EXTRA_CFLAGS' sanitizers (s51_fastpoll.c)
$(FX2_FASTPOLL): firmware/fx2/test/s51_fastpoll.c
	@mkdir -p $(dir $@)
	$(CC) -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) -O2 -shared -fPIC $< -o $@

firmware-check: $(FX2_S51) $(FX2_FASTPOLL) $(FX2_IHX)
	@bash tests/firmware-s51.sh $(BUILD)

$(FX2_SPEED_STREAM): $(ALBATROS)
	@mkdir -p $(dir $@)
	$(ALBATROS) gp -q -o $@

# both timings, in one run: s51's classic core (its clocks checked against the
# opcode counts) and its Dallas 4-clock core (a second figure for the FX2's)
firmware-speed: $(FX2_S51) $(FX2_FASTPOLL) $(FX2_IHX) $(FX2_SPEED_STREAM)
	$(FX2_S51) speed $(FX2_IHX) $(FX2_SPEED_STREAM) --fps $(FX2_FPS) --profile
