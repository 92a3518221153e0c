# rtl.mk — the reference RTL of the VP (rtl/README.md), included from the
# top Makefile.  The Verilator benches are built per parameter set into
# $(BUILD)/rtl/ by tests/cosim.sh (rtl/bench/verilate.sh) and reused while
# the RTL is unchanged.
.PHONY: cosim cosim-quick rtl-lint rtl-synth

# everything: every golden vector, 200+ random scenes over the odd parameter
# sets, the stress families, three profiles, Icarus, the planted mutations
cosim: $(ALBATROS)
	@bash tests/cosim.sh $(BUILD) --all

# the subset make test runs
cosim-quick: $(ALBATROS)
	@bash tests/cosim.sh $(BUILD)

rtl-lint:
	verilator --lint-only -Wall -Irtl --top-module alb_vp rtl/alb_*.sv

# yosys's generic synthesis of the whole VP (a small member), checked for
# latches: slow (tens of minutes), so not part of make cosim
rtl-synth:
	@bash tests/cosim.sh $(BUILD) --synth

# the RTL board of `albatros stream --sim=rtl` for one profile (rtl/board/,
# docs/usb-protocol.md): make rtl-board PROFILE=a256 [SET='edge_units=3 ...']
# [RTL='FOG_UNIT=0 ...'] [RTL_BOARD_DIR=DIR]; without SET it goes where
# albatros looks for it (RTL: parameters of the RTL's own, rtl/README.md)
PROFILE ?= t32
RTL_BOARD_DIR ?= $(BUILD)/rtl-board/$(PROFILE)
.PHONY: rtl-board
rtl-board: $(ALBATROS) $(LIBALB_SO)
	@ALBATROS=$(ALBATROS) ALB_LIB=$(BUILD)/lib bash rtl/board/build.sh $(RTL_BOARD_DIR) $(PROFILE) \
	  $(foreach s,$(SET),--set $(s)) $(foreach r,$(RTL),--rtl $(r))
	@echo "rtl-board: $(RTL_BOARD_DIR)/albatros-rtl-board.so"
