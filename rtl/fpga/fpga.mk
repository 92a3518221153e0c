# fpga.mk — the VP on an FPGA and the family's design-space view
# (docs/fpga.md), included from the top Makefile.
.PHONY: fpga fpga-check fpga-top fpga-sweep fpga-sweep-chart fpga-sweep-prep fpga-sweep-jobs

FPGA_PROFILE ?= up5k
# the board (rtl/fpga/fpga.sh --board): hx8k-breakout or icebreaker
FPGA_BOARD ?= hx8k-breakout
# more of the RTL's own sizes than rtl/fpga/board.sizes (fpga.sh --rtl), e.g.
# FPGA_RTL="FOG_UNIT=1"
FPGA_RTL ?=
# --noabc: the sweep's synthesis without ABC (docs/fpga.md)
FPGA_SWEEP_ABC ?=

# yosys synth_ice40, nextpnr-ice40 (--report), icepack: $(BUILD)/fpga/ (the
# HX8K breakout's iCE40HX8K by default)
fpga: $(ALBATROS)
	@bash rtl/fpga/fpga.sh --build $(BUILD) --profile $(FPGA_PROFILE) --board $(FPGA_BOARD) $(FPGA_RTL:%=--rtl %)

# the real flow, then its report judged: fits the part, meets the VP's clock
# (the profile's clock_khz) and the FX2's 48 MHz IFCLK
fpga-check: $(ALBATROS)
	@rm -f $(BUILD)/fpga/report.json $(BUILD)/fpga/pack-report.json
	@bash rtl/fpga/fpga.sh --build $(BUILD) --profile $(FPGA_PROFILE) --board $(FPGA_BOARD) $(FPGA_RTL:%=--rtl %) || true
	@r=$(BUILD)/fpga/report.json; [ -e $$r ] || r=$(BUILD)/fpga/pack-report.json; \
	python3 rtl/fpga/fpga_report.py $$r \
	    --clock clk_vp=$$(awk '{ print $$1 / 1000 }' $(BUILD)/fpga/clock_khz) --clock ifclk=48

# alb_fpga_top simulated with the FX2's side of the board, every RESULT
# against the model (rtl/fpga/README.md), and the planted bugs it must catch
# (a Verilator build each: about five minutes; make test runs the cases only)
fpga-top: $(ALBATROS) $(LIBALB_SO)
	@bash tests/fpga-top.sh $(BUILD) --mutations

# the design-space view (docs/fpga.md): one job per point and unit (yosys's
# generic synth of that unit at the point's parameters) and one per point
# (the cycle model), cached per unit and parameters; make -j2 fpga-sweep, or
# make fpga-sweep-jobs | parallel, then make fpga-sweep to collect.
FPGA_SWEEP_POINTS := a512:a512 \
    a512-eu1:a512:edge_units=1 a512-eu2:a512:edge_units=2 a512-eu4:a512:edge_units=4 \
    a512-eu16:a512:edge_units=16 a512-fr1:a512:fill_rate=1 a512-fr2:a512:fill_rate=2 \
    a512-fr8:a512:fill_rate=8 a512-fs1:a512:face_slots=1 a512-fs4:a512:face_slots=4 \
    a1024:a1024
# the units whose jobs take under 3 minutes here (docs/fpga.md); the
# pipeline's takes more: FPGA_SWEEP_LONG=1 adds it
FPGA_SWEEP_UNITS := alb_fifo alb_parser alb_edge_store alb_engine alb_fill_queue alb_fill \
    alb_frame_store alb_frame_crc
ifeq ($(FPGA_SWEEP_LONG),1)
FPGA_SWEEP_UNITS += alb_pipe
endif
FPGA_SWEEP_FAMILIES := interpenetrating deep
FPGA_SWEEP_SEVERITY := 0.5
FPGA_SWEEP_DIR := $(BUILD)/fpga-sweep
fpga_sweep_name = $(word 1,$(subst :, ,$(1)))
fpga_sweep_prof = $(word 2,$(subst :, ,$(1)))
fpga_sweep_sets = $(patsubst %,--set %,$(wordlist 3,9,$(subst :, ,$(1))))
FPGA_SWEEP_NAMES := $(foreach p,$(FPGA_SWEEP_POINTS),$(call fpga_sweep_name,$(p)))
FPGA_SWEEP_SCENES := $(FPGA_SWEEP_FAMILIES:%=$(FPGA_SWEEP_DIR)/scenes/%.scene)
FPGA_SWEEP_OUTS := $(foreach n,$(FPGA_SWEEP_NAMES),$(FPGA_SWEEP_DIR)/$(n)/cycles \
    $(FPGA_SWEEP_UNITS:%=$(FPGA_SWEEP_DIR)/$(n)/%.unit))
FPGA_SWEEP_RTL := $(wildcard rtl/*.sv rtl/*.svh) rtl/fpga/sweep-unit.sh \
    rtl/fpga/sweep_units.py rtl/fpga/sweep_stat.py

$(FPGA_SWEEP_DIR)/scenes/%.scene: $(ALBATROS)
	@mkdir -p $(dir $@)
	@$(ALBATROS) scene $* --severity $(FPGA_SWEEP_SEVERITY) -o $@ > /dev/null

define fpga_sweep_point
$(FPGA_SWEEP_DIR)/$(call fpga_sweep_name,$(1))/params: $(ALBATROS) rtl/profile-params.sh
	@mkdir -p $$(dir $$@)
	@rtl/profile-params.sh --albatros $(ALBATROS) --format shell $(call fpga_sweep_prof,$(1)) \
	    $(call fpga_sweep_sets,$(1)) > $$@.tmp && mv $$@.tmp $$@
$(FPGA_SWEEP_DIR)/$(call fpga_sweep_name,$(1))/cycles: $(ALBATROS) rtl/fpga/sweep-cycles.sh \
	    $(FPGA_SWEEP_SCENES)
	@mkdir -p $$(dir $$@)
	@bash rtl/fpga/sweep-cycles.sh $(ALBATROS) $$@ $(FPGA_SWEEP_DIR)/scenes \
	    $(call fpga_sweep_prof,$(1)) $(call fpga_sweep_sets,$(1))
$(FPGA_SWEEP_DIR)/$(call fpga_sweep_name,$(1))/%.unit: \
	    $(FPGA_SWEEP_DIR)/$(call fpga_sweep_name,$(1))/params $(FPGA_SWEEP_RTL)
	@echo "fpga-sweep: $(call fpga_sweep_name,$(1)) $$*"
	@bash rtl/fpga/sweep-unit.sh $$@ $$* $(FPGA_SWEEP_ABC) $$$$(cat $$<)
endef
$(foreach p,$(FPGA_SWEEP_POINTS),$(eval $(call fpga_sweep_point,$(p))))

fpga-sweep: $(FPGA_SWEEP_OUTS)
	@mkdir -p docs/fpga
	@python3 rtl/fpga/sweep_collect.py $(FPGA_SWEEP_DIR) --units "$(FPGA_SWEEP_UNITS)" \
	    --families "$(FPGA_SWEEP_FAMILIES)" $(FPGA_SWEEP_POINTS) > docs/fpga/sweep.csv.tmp
	@mv docs/fpga/sweep.csv.tmp docs/fpga/sweep.csv
	@$(MAKE) --no-print-directory fpga-sweep-chart

# the jobs as shell commands, one a line, for GNU parallel or a Slurm array
# (the params and scenes first: make fpga-sweep-prep)
fpga-sweep-prep: $(FPGA_SWEEP_SCENES) \
    $(foreach n,$(FPGA_SWEEP_NAMES),$(FPGA_SWEEP_DIR)/$(n)/params)
fpga-sweep-jobs: fpga-sweep-prep
	@$(foreach p,$(FPGA_SWEEP_POINTS),echo 'bash rtl/fpga/sweep-cycles.sh $(ALBATROS) \
	    $(FPGA_SWEEP_DIR)/$(call fpga_sweep_name,$(p))/cycles $(FPGA_SWEEP_DIR)/scenes \
	    $(call fpga_sweep_prof,$(p)) $(call fpga_sweep_sets,$(p))';)
	@$(foreach n,$(FPGA_SWEEP_NAMES),$(foreach u,$(FPGA_SWEEP_UNITS),\
	    echo 'bash rtl/fpga/sweep-unit.sh $(FPGA_SWEEP_DIR)/$(n)/$(u).unit $(u) $(FPGA_SWEEP_ABC) '"$$(echo $$(cat $(FPGA_SWEEP_DIR)/$(n)/params))";))

fpga-sweep-chart:
	@cd docs/fpga && gnuplot sweep.gp && mv sweep.svg.tmp sweep.svg && echo "docs/fpga/sweep.svg from docs/fpga/sweep.csv"
