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
