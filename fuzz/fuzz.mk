# ---- fuzzing (fuzz/README.md): libFuzzer harnesses, one per input path ----
# make fuzz-TARGET [FUZZ_TIME=600]   fuzz one input path with clang + libFuzzer
# make fuzz-build                    build every fuzzer (build-fuzz/fuzz_TARGET)
# make fuzz-replay                   the harnesses without libFuzzer, over the
#                                    seeds and the regression inputs (make test)
FUZZ_TARGETS := scene obj stream png options fw link
FUZZ_BUILD   ?= build-fuzz
FUZZ_TIME    ?= 600
FUZZ_ARGS    ?=
FUZZERS      := $(addprefix $(FUZZ_BUILD)/fuzz_,$(FUZZ_TARGETS))
REPLAYS      := $(addprefix $(BUILD)/fuzz/replay_,$(FUZZ_TARGETS))
FUZZ_OBJ     := $(BUILD)/fuzz/common.o $(BUILD)/emu/cli.o

.PHONY: fuzz-build fuzz-replay $(addprefix fuzz-,$(FUZZ_TARGETS))

# Every object is built for the fuzzer (coverage, ASan, UBSan) by clang in
# $(FUZZ_BUILD); the harness links libFuzzer's main.
fuzz-build:
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) BUILD=$(FUZZ_BUILD) CC=clang OPT=-O1 \
	  EXTRA_CFLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
	  EXTRA_LDLIBS="-fsanitize=fuzzer,address,undefined" $(FUZZERS)

$(addprefix $(BUILD)/fuzz_,$(FUZZ_TARGETS)): $(BUILD)/fuzz_%: $(BUILD)/fuzz/fuzz_%.o $(FUZZ_OBJ) $(LIB_OBJ)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

# The corpus grows in $(FUZZ_BUILD)/corpus-TARGET (seeded from fuzz/corpus);
# crashes land in $(FUZZ_BUILD)/ as crash-*, leak-*, timeout-*: minimise them
# with -minimize_crash=1 and keep them in fuzz/regress/TARGET/.  The scratch
# directories of crashed runs stay behind in $(FUZZ_BUILD)/tmp, not /tmp.
$(addprefix fuzz-,$(FUZZ_TARGETS)): fuzz-%: fuzz-build
	@mkdir -p $(FUZZ_BUILD)/corpus-$* $(FUZZ_BUILD)/tmp
	TMPDIR=$(abspath $(FUZZ_BUILD))/tmp $(FUZZ_BUILD)/fuzz_$* -max_total_time=$(FUZZ_TIME) -timeout=10 -rss_limit_mb=2048 \
	  -detect_leaks=1 -dict=fuzz/$*.dict -artifact_prefix=$(FUZZ_BUILD)/ \
	  $(FUZZ_ARGS) $(FUZZ_BUILD)/corpus-$* fuzz/corpus/$*

$(REPLAYS): $(BUILD)/fuzz/replay_%: $(BUILD)/fuzz/fuzz_%.o $(BUILD)/fuzz/replay.o $(FUZZ_OBJ) $(LIB_OBJ)
	$(CC) $(ALL_CFLAGS) $^ $(LDLIBS) -o $@

fuzz-replay: $(REPLAYS)
	@bash tests/fuzz-replay.sh $(BUILD)
