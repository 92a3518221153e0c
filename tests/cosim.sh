#!/usr/bin/env bash
# cosim.sh [BUILD] [--all | --synth] — the reference RTL (rtl/) held against the
# cycle model: lint and synthesis checks, then streams through both, every event of
# docs/cosim.md compared cycle by cycle (rtl/bench/cosim.cpp), and the Icarus
# bench.  Without --all a fast subset (make test); --all is make cosim: every
# golden vector, 200+ random scenes over the odd parameter sets, the stress
# families, three profiles, and the planted mutations; --synth is make
# rtl-synth, yosys's generic synthesis of the whole VP alone.  Ends with
# "N passed, N failed".  A divergence leaves its waveform in BUILD/cosim/.
set -u
build=build all=0 synth=0
for a in "$@"; do
    case $a in
        --all) all=1 ;;
        --synth) synth=1 ;;
        -*) echo "usage: cosim.sh [BUILD] [--all | --synth]" >&2; exit 2 ;;
        *) build=$a ;;
    esac
done
bin=$build/albatros
out=$build/cosim
export ALB_LIB=$build/lib     # the benches link this build's libalbatros
# a library built under ASan/UBSan (make asan) needs their runtime first in
# the bench: linked in, the bench's own code uninstrumented
if ldd "$build/lib/libalbatros.so" 2>/dev/null | grep -q 'libasan'; then
    export ALB_BENCH_LDFLAGS="-fsanitize=address,undefined"
fi
mkdir -p "$out"
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; [[ -n ${2:-} ]] && sed 's/^/     /' "$2" | tail -n 12; }

for tool in verilator iverilog yosys; do
    if ! command -v $tool >/dev/null; then
        bad "$tool is not installed (make setup installs it; rtl/README.md)"
    fi
done
[[ -x $bin ]] || bad "$bin is missing: build it with make"
if ((fail)); then echo "$pass passed, $fail failed"; exit 1; fi

rtl_files=(rtl/alb_fifo.sv rtl/alb_parser.sv rtl/alb_edge_store.sv rtl/alb_engine.sv
           rtl/alb_fill_queue.sv rtl/alb_fill.sv rtl/alb_pipe_reg.sv rtl/alb_pipe.sv rtl/alb_frame_store.sv
           rtl/alb_frame_crc.sv rtl/alb_vp.sv)

# ---- lint and synthesis ----

lint() {   # NAME PROFILE-ARGS...
    local name=$1; shift
    local log=$out/lint-$name.log params
    params=$(rtl/profile-params.sh --albatros "$bin" "$@") || { bad "lint $name: profile" ; return; }
    # shellcheck disable=SC2086
    if verilator --lint-only -Wall -Irtl --top-module alb_vp $params "${rtl_files[@]}" \
        > "$log" 2>&1 && [[ ! -s $log ]]; then
        ok "lint $name (verilator -Wall)"
    else
        bad "lint $name (verilator -Wall)" "$log"
    fi
}

synth_check() {   # FULL: yosys: no latches anywhere, no multiplier in the classifier
    local full=$1 log=$out/yosys.log script what
    # a small member: the checks are about structure, not size; -defer, so
    # yosys never elaborates the default 2^15-word reciprocal ROM
    local chp="-chparam RECIP_BITS 8 -chparam TEX_WORDS 64 -chparam FIFO_DEPTH 4 -chparam FILL_RATE 2"
    local latches="select -assert-none t:\$dlatch t:\$adlatch t:\$dlatchsr t:\$_DLATCH_* t:\$_DLATCHSR_*"
    if ((full)); then
        script="synth -top alb_vp; $latches"   # generic synthesis, to gates
        what="yosys synth (generic): no latches"
    else
        script="proc; opt -fast; $latches"     # where latches are inferred
        what="yosys proc: no latches"
    fi
    if yosys -q -l "$log" -p "read_verilog -defer -sv -Irtl ${rtl_files[*]};
            hierarchy -top alb_vp $chp; $script; tee -o $out/yosys.stat stat -top alb_vp" \
        > /dev/null 2>&1; then
        ok "$what"
    else
        bad "$what" "$log"
    fi
    log=$out/yosys-engine.log
    if yosys -q -l "$log" -p "read_verilog -sv -Irtl rtl/alb_engine.sv;
            hierarchy -top alb_engine; proc; opt; wreduce;
            select -assert-count 0 t:\$mul t:\$div t:\$mod t:\$divfloor t:\$modfloor t:\$pow;
            select -assert-min 1 t:\$add" > /dev/null 2>&1; then
        ok "yosys: the classifier (alb_engine) has adders and no multiplier"
    else
        bad "yosys: the classifier (alb_engine) has adders and no multiplier" "$log"
    fi
}

if ((synth)); then   # make rtl-synth: the generic synthesis alone
    synth_check 1
    echo "$pass passed, $fail failed"
    [[ $fail -eq 0 ]]
    exit
fi

# ---- co-simulation ----

# model NAME PROFILE [--set k=v ...]: the Verilator bench for that parameter
# set, in BUILD/rtl/NAME (built once, reused while the RTL is unchanged).  The
# output stage scans a quarter of a row a cycle, so frames of a few thousand
# cycles are scanned out before the next retires (rtl/README.md).
declare -A model_ok
model() {
    local name=$1; shift
    [[ -n ${model_ok[$name]:-} ]] && return "${model_ok[$name]}"
    local width params
    width=$(rtl/profile-params.sh --albatros "$bin" --format shell "$@" | sed -n 's/^WIDTH=//p')
    params=$(rtl/profile-params.sh --albatros "$bin" "$@" --rtl SCAN_PIXELS=$(( width >= 4 ? width / 4 : 1 ))) ||
        { model_ok[$name]=1; return 1; }
    # shellcheck disable=SC2086
    if rtl/bench/verilate.sh "$build/rtl/$name" $params > "$out/build-$name.log" 2>&1; then
        model_ok[$name]=0
    else
        bad "build $name" "$out/build-$name.log"
        model_ok[$name]=1
    fi
    return "${model_ok[$name]}"
}

# cosim_stream CASE MODEL STREAM PROFILE-ARGS...: the stream through the cycle
# model (its event log) and the RTL
cosim_stream() {
    local case=$1 name=$2 stream=$3; shift 3
    local dir=$out/$case
    mkdir -p "$dir"
    if ! "$bin" vp "$stream" "$@" --fidelity cycle --events "$dir/model.log" -q \
        > "$dir/model.out" 2>&1; then
        bad "$case: the model refused the stream" "$dir/model.out"
        return
    fi
    if "$build/rtl/$name/cosim" --events "$dir/model.log" --stream "$stream" \
        --log "$dir/rtl.log" --vcd "$dir/divergence.vcd" > "$dir/cosim.out" 2>&1; then
        ok "$case: $(tail -n 1 "$dir/cosim.out" | sed 's/^cosim: //')"
        rm -f "$dir/model.log" "$dir/rtl.log"     # large; kept only when they differ
    else
        bad "$case" "$dir/cosim.out"
    fi
}

# cosim_scene CASE MODEL SCENE PROFILE-ARGS...: through the GP first
cosim_scene() {
    local case=$1 name=$2 scene=$3; shift 3
    mkdir -p "$out/$case"
    if ! "$bin" gp "$scene" "$@" -o "$out/$case/s.stream" > "$out/$case/gp.out" 2>&1; then
        bad "$case: gp" "$out/$case/gp.out"
        return
    fi
    cosim_stream "$case" "$name" "$out/$case/s.stream" "$@"
}

# cosim_random CASE MODEL SEED FACES [--flat] -- PROFILE-ARGS...
cosim_random() {
    local case=$1 name=$2 seed=$3 faces=$4; shift 4
    local flat=()
    if [[ ${1:-} == --flat ]]; then flat=(--flat); shift; fi
    [[ ${1:-} == -- ]] && shift
    mkdir -p "$out/$case"
    "$bin" scene random --faces "$faces" --seed "$seed" "${flat[@]}" -o "$out/$case/s.scene" \
        > /dev/null 2>&1 || { bad "$case: scene random"; return; }
    cosim_scene "$case" "$name" "$out/$case/s.scene" "$@"
}

# the profile options of a golden vector (the GP's own options are not the VP's)
vector_profile() {
    grep -v '^#' "test-vectors/$1/options" | tr ' ' '\n' |
        awk '/^--profile$|^--set$/ { k = $0; next } k { print k; print; k = "" }'
}

cosim_vector() {   # CASE-PREFIX VECTOR
    local v=$2 prof name
    mapfile -t prof < <(vector_profile "$v")
    name=$(printf '%s' "${prof[*]}" | tr -c 'A-Za-z0-9=_' '-' | sed 's/^--profile-//')
    model "$name" "${prof[@]}" || return
    cosim_stream "$1$v" "$name" "test-vectors/$v/expected.stream" "${prof[@]}"
}

# ---- Icarus ----

icarus() {   # CASE SCENE PROFILE-ARGS...: the plain SystemVerilog bench
    local case=$1 scene=$2; shift 2
    if bash rtl/bench/icarus.sh --albatros "$bin" --dir "$out/$case" "$scene" "$@" \
        > "$out/$case.out" 2>&1; then
        ok "$case: $(tail -n 1 "$out/$case.out")"
    else
        bad "$case" "$out/$case.out"
    fi
}

lint t32 t32
lint a512 a512
lint odd t32 --set aa=2 --set fill_rate=1 --set edge_units=1 --set face_slots=1 \
    --set fifo_depth=2 --set divider_latency=0 --set shade_latency=0 --set fill_queue=1
lint wide a256 --set width=512 --set height=128 --set fill_rate=8 --set edge_units=3
lint up5k up5k --rtl MAX_EDGES=6 --rtl TEX_WORDS=256 --rtl TEX_IDS=4 --rtl TAG_BITS=8   # the FPGA sizes, every unit
# the FPGA board's build: its sizes are rtl/fpga/board.sizes (flat faces only)
board_rtl=$(sed -e 's/#.*//' -e '/^ *$/d' -e 's/^/--rtl /' rtl/fpga/board.sizes)
# shellcheck disable=SC2086
lint up5k-flat up5k $board_rtl
synth_check 0

if model t32 t32; then
    cosim_scene ties t32 rtl/bench/scenes/ties.scene --profile t32
    cosim_scene empty-frames t32 rtl/bench/scenes/empty-frames.scene --profile t32
    cosim_random t32-random-1 t32 1 30 -- --profile t32
    cosim_random t32-random-2-flat t32 2 30 --flat -- --profile t32
    mkdir -p "$out/t32-builtin"
    "$bin" gp --profile t32 -o "$out/t32-builtin/s.stream" > /dev/null 2>&1 &&
        cosim_stream t32-builtin t32 "$out/t32-builtin/s.stream" --profile t32
fi
# the RTL's resolved frames (its frame store dumped as docs/cosim.md lays it
# out) against the model's, with anti-aliasing: the built-in scene's 4 frames
if model t32-aa1 t32 --set aa=1; then
    d=$out/dump-t32-aa1
    mkdir -p "$d"
    if "$bin" gp --profile t32 --set aa=1 -o "$d/s.stream" > /dev/null 2>&1 &&
        "$bin" vp "$d/s.stream" --profile t32 --set aa=1 --fidelity cycle --events "$d/model.log" \
            --dump "$d/model.memh" -q > /dev/null 2>&1 &&
        "$build/rtl/t32-aa1/cosim" --events "$d/model.log" --dump "$d/rtl" > "$d/cosim.out" 2>&1; then
        same=0
        for f in "$d"/model.*.memh; do
            r=$d/rtl.${f#"$d"/model.}
            cmp -s <(grep -v '^//' "$f") <(grep -v '^//' "$r") &&
                "$bin" compare "$r" "$f" --profile t32 --set aa=1 > /dev/null 2>&1 && same=$((same + 1))
        done
        if ((same == 4)); then
            ok "dump-t32-aa1: the RTL's 4 resolved frames equal the model's (albatros compare)"
        else
            bad "dump-t32-aa1: $same of 4 frames equal the model's" "$d/cosim.out"
        fi
    else
        bad "dump-t32-aa1" "$d/cosim.out"
    fi
fi
for v in shared-edges textured-far-plane moving-lit; do
    cosim_vector vector- "$v"
done
icarus icarus-ties rtl/bench/scenes/ties.scene --profile t32

# the FPGA build's sizes (rtl/fpga/fpga.sh: up5k, the depth store answering
# in the next cycle as block RAM does, six edges a face, four texture ids):
# the built-in scene through both, event by event
if model up5k-fpga up5k --rtl ZR_REG=1 --rtl MAX_EDGES=6 --rtl TEX_IDS=4 --rtl TAG_BITS=8; then
    mkdir -p "$out/up5k-builtin"
    "$bin" gp --profile up5k -o "$out/up5k-builtin/s.stream" > /dev/null 2>&1 &&
        cosim_stream up5k-builtin up5k-fpga "$out/up5k-builtin/s.stream" --profile up5k
fi
# a texture memory smaller than a texture (the built-in scene's first, 64 x 64
# at word 3, against 256 texels) is refused there, E_TEX_FULL (12); a size
# held in the memory's address width wrapped 4096 to 0 and drew wrong texels
if model t32-tex256 t32 --rtl TEX_WORDS=256; then
    if "$build/rtl/t32-tex256/cosim" --stream "$out/t32-builtin/s.stream" --expect-error 12@3 \
        > "$out/t32-tex256.out" 2>&1; then
        ok "t32-tex256: $(sed 's/^cosim: //' "$out/t32-tex256.out")"
    else
        bad "t32-tex256: a texture larger than TEX_WORDS" "$out/t32-tex256.out"
    fi
fi

# Builds that leave shading units out (SHADE_UNIT, TEX_UNIT, FOG_UNIT 0;
# rtl/README.md): what they draw is the model's, event by event, and what
# needs a unit left out is refused, E_UNIT (17), at the word the model's
# stream dump (albatros gp --hex) shows: a TEXTURE's header, a FACE's header
# (its flags), a FRAME's fog word (header + 2).
expect_error() {   # CASE MODEL STREAM CODE@WORD
    if "$build/rtl/$2/cosim" --stream "$3" --expect-error "$4" > "$out/$1.out" 2>&1; then
        ok "$1: $(sed 's/^cosim: //' "$out/$1.out")"
    else
        bad "$1: expected error $4" "$out/$1.out"
    fi
}
first_word() {     # HEX AWK-CONDITION: the index of the first word whose dump line matches
    local off
    off=$(awk "$2 { print \$1; exit }" "$1")
    [[ -n $off ]] && echo $((16#$off / 4))
}
u=$out/units
mkdir -p "$u"
"$bin" gp --profile t32 -o "$u/b32.stream" --hex "$u/b32.hex" -q > /dev/null 2>&1 ||
    bad "units: gp of the built-in scene at t32"
"$bin" gp --profile up5k -o "$u/b5.stream" --hex "$u/b5.hex" -q > /dev/null 2>&1 ||
    bad "units: gp of the built-in scene at up5k"
# the FPGA build's sizes with flat shading only: flat faces of at most four
# vertices (six edges with the bounding ones), four frames, the depth test
# lost often; the built-in scene's first TEXTURE refused; and a stream
# without TEXTURE packets or fog (tex-fog-flat.scene without its fog, its
# TEXTUREs cut out) refused at its first textured FACE
# shellcheck disable=SC2086
if model up5k-flat up5k --rtl ZR_REG=1 $board_rtl; then
    cosim_scene up5k-flat-quads up5k-flat rtl/bench/scenes/flat-quads.scene --profile up5k
    n=$(first_word "$u/b5.hex" '$3 == "TEXTURE"')
    expect_error up5k-flat-texture up5k-flat "$u/b5.stream" "17@${n:-none}"
    grep -v '^fog ' rtl/bench/scenes/tex-fog-flat.scene > "$u/tex-flat.scene"
    "$bin" gp "$u/tex-flat.scene" --profile up5k --hex - -q 2> /dev/null |
        awk '$3 != "TEXTURE" && $3 !~ /^texel/' > "$u/notex.hex"
    python3 -c 'import struct, sys
sys.stdout.buffer.write(b"".join(struct.pack("<I", int(l.split()[1], 16)) for l in sys.stdin))' \
        < "$u/notex.hex" > "$u/notex.stream"
    # (renumbered: the index is the line's, the offsets are the uncut stream's)
    n=$(awk '$3 == "FACE" { print NR - 1 ($5 ~ /^flags=-T/ ? "" : " not-textured-only"); exit }' "$u/notex.hex")
    expect_error up5k-flat-textured-face up5k-flat "$u/notex.stream" "17@${n:-none}"
fi
# without the shade unit: textures and fog drawn as the model does; the
# built-in scene (its textures loaded) refused at its first Gouraud FACE
if model t32-noshade t32 --rtl SHADE_UNIT=0; then
    cosim_scene t32-noshade-tex-fog t32-noshade rtl/bench/scenes/tex-fog-flat.scene --profile t32
    n=$(first_word "$u/b32.hex" '$3 == "FACE" && $5 ~ /^flags=S/')
    expect_error t32-noshade-shaded-face t32-noshade "$u/b32.stream" "17@${n:-none}"
fi
# without the fog unit: textures and Gouraud shading drawn as the model
# does; the built-in scene refused at its first FRAME's fog word
if model t32-nofog t32 --rtl FOG_UNIT=0; then
    cosim_scene t32-nofog-tex-shade t32-nofog rtl/bench/scenes/tex-shade.scene --profile t32
    n=$(first_word "$u/b32.hex" '$3 ~ /^frame.fog=on/')
    expect_error t32-nofog-fogged-frame t32-nofog "$u/b32.stream" "17@${n:-none}"
fi

# malformed streams: the RTL's error output names the error and its word
while IFS='|' read -r file prof want; do
    file=$(echo $file) prof=$(echo $prof) want=$(echo $want)
    [[ -z $file || $file == \#* ]] && continue
    model "$prof" "$prof" || continue
    if "$build/rtl/$prof/cosim" --stream "tests/data/malformed/$file" --expect-error "$want" \
        > "$out/malformed-$file.out" 2>&1; then
        ok "malformed $file: $(sed 's/^cosim: //' "$out/malformed-$file.out")"
    else
        bad "malformed $file" "$out/malformed-$file.out"
    fi
done < rtl/bench/malformed.txt

if ((all)); then
    # every golden vector (three profiles: a256, a512, a1024x512)
    for d in test-vectors/*/; do
        v=$(basename "$d")
        [[ -f $d/README && $v != shared-edges && $v != textured-far-plane && $v != moving-lit ]] &&
            cosim_vector vector- "$v"
    done
    # random scenes under the parameter sets that force stalls and corners:
    # 8 sets x 13 seeds x 2 (shaded, flat) = 208 scenes
    sets=("t32" "t32 --set edge_units=1" "t32 --set edge_units=3" "t32 --set fill_rate=1"
          "t32 --set fill_rate=8" "t32 --set fifo_depth=2" "t32 --set face_slots=1"
          "t32 --set aa=1")
    for s in "${sets[@]}"; do
        read -ra args <<< "$s"
        name=$(printf '%s' "$s" | tr -c 'A-Za-z0-9=_' '-')
        model "$name" "${args[@]}" || continue
        for seed in $(seq 101 113); do
            cosim_random "random-$name-$seed" "$name" "$seed" 40 -- --profile "${args[@]}"
            cosim_random "random-$name-$seed-flat" "$name" "$seed" 40 --flat -- --profile "${args[@]}"
        done
    done
    # more corners: no pipeline latency, one-cell queue and one of everything
    for s in "t32 --set divider_latency=0 --set shade_latency=0" \
             "t32 --set fill_queue=1 --set edge_units=1 --set fill_rate=1 --set face_slots=1" \
             "t32 --set aa=3 --set fill_rate=8"; do
        read -ra args <<< "$s"
        name=$(printf '%s' "$s" | tr -c 'A-Za-z0-9=_' '-')
        model "$name" "${args[@]}" || continue
        for seed in 201 202 203; do
            cosim_random "random-$name-$seed" "$name" "$seed" 40 -- --profile "${args[@]}"
        done
        cosim_scene "ties-$name" "$name" rtl/bench/scenes/ties.scene --profile "${args[@]}"
    done
    # the stress families of albatros stability (docs/stability.md), at a256
    if model a256 a256; then
        for fam in sliver crossing-z0 far texture-far interpenetrating cyclic degenerate \
                   tjunction deep coords; do
            for sev in 0.3 0.9; do
                c=stress-$fam-$sev
                mkdir -p "$out/$c"
                if "$bin" scene "$fam" --severity "$sev" -o "$out/$c/s.scene" > /dev/null 2>&1; then
                    cosim_scene "$c" a256 "$out/$c/s.scene" --profile a256
                else
                    bad "$c: scene"
                fi
            done
        done
    fi
    # the FRAME registers full (profile frame_queue): with 2 sets, the FRAMEs
    # of the empty frames wait for retirements, blocked, in both
    if model t32-fq2 t32 --set frame_queue=2; then
        cosim_scene empty-frames-fq2 t32-fq2 rtl/bench/scenes/empty-frames.scene --profile t32 \
            --set frame_queue=2
    fi
    icarus icarus-random "$out/t32-random-1/s.scene" --profile t32
    # the second simulator on the small golden vectors (a256, one frame each
    # but moving-lit's four)
    for v in sliver-none sliver-albatros sliver-box sliver-bisector shared-edges obj-cube \
             bound-at-most-two textured-far-plane moving-lit; do
        mapfile -t prof < <(vector_profile "$v")
        icarus "icarus-$v" "test-vectors/$v/expected.stream" "${prof[@]}"
    done
    # the planted bugs: each must make the bench fail at its event
    if bash rtl/bench/mutations.sh --albatros "$bin" --dir "$out/mutations" > "$out/mutations.out" 2>&1; then
        ok "mutations: $(tail -n 1 "$out/mutations.out")"
    else
        bad "mutations" "$out/mutations.out"
    fi
fi

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
