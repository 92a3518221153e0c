# fpga.mk — the VP on an FPGA and the family's design-space view
# (docs/fpga.md), included from the top Makefile.
.PHONY: fpga fpga-check fpga-sweep fpga-sweep-chart

FPGA_PROFILE ?= up5k

# yosys synth_ice40, nextpnr-ice40 (--report), icepack: $(BUILD)/fpga/ (the
# iCEBreaker's UP5K)
fpga: $(ALBATROS)
	@bash rtl/fpga/fpga.sh --build $(BUILD) --profile $(FPGA_PROFILE)

# the real flow, then its report judged: fits the part, meets the VP's clock
# (the profile's clock_khz) and the FX2's 48 MHz IFCLK
fpga-check: $(ALBATROS)
	@bash rtl/fpga/fpga.sh --build $(BUILD) --profile $(FPGA_PROFILE) || true
	@r=$(BUILD)/fpga/report.json; [ -e $$r ] || r=$(BUILD)/fpga/pack-report.json; \
	python3 rtl/fpga/fpga_report.py $$r \
	    --clock clk_vp=$$(awk '{ print $$1 / 1000 }' $(BUILD)/fpga/clock_khz) --clock ifclk=48

# one job per point: make -j fpga-sweep
SWEEP_POINTS := a512:a512 a1024:a1024 \
    a512-eu1:a512:edge_units=1 a512-eu2:a512:edge_units=2 a512-eu4:a512:edge_units=4 \
    a512-eu16:a512:edge_units=16 a512-fr1:a512:fill_rate=1 a512-fr2:a512:fill_rate=2 \
    a512-fr8:a512:fill_rate=8 a512-fs1:a512:face_slots=1 a512-fs4:a512:face_slots=4
SWEEP_DIR := $(BUILD)/fpga-sweep
sweep_name = $(word 1,$(subst :, ,$(1)))
SWEEP_CSVS := $(foreach p,$(SWEEP_POINTS),$(SWEEP_DIR)/$(call sweep_name,$(p)).csv)

$(SWEEP_DIR)/%.csv: $(ALBATROS) rtl/fpga/sweep-point.sh $(wildcard rtl/*.sv)
	@p='$(filter $*:%,$(SWEEP_POINTS))'; set -- $$(echo "$$p" | tr ':' ' '); \
	 name=$$1 prof=$$2; shift 2; sets=""; for s in "$$@"; do sets="$$sets --set $$s"; done; \
	 echo "fpga-sweep: $$name"; bash rtl/fpga/sweep-point.sh $(BUILD) $$name $$prof $$sets

fpga-sweep: $(SWEEP_CSVS)
	@mkdir -p docs/fpga
	@{ echo "point,member,cells,parser,edge_store,engine,fill_queue,fill,pipe,frame_store,frame_crc,fifo_top,cycles_builtin,cycles_interpenetrating,cycles_deep"; \
	   cat $(SWEEP_CSVS); } > docs/fpga/sweep.csv
	@$(MAKE) --no-print-directory fpga-sweep-chart

fpga-sweep-chart:
	@cd docs/fpga && gnuplot sweep.gp && echo "docs/fpga/sweep.svg from docs/fpga/sweep.csv"
