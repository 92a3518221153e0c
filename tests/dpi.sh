#!/usr/bin/env bash
# dpi.sh BUILD — every golden vector replayed from SystemVerilog through the
# model over DPI-C (tests/dpi/tb_vector.sv, built by Verilator against
# libalbatros.so): each frame's number, cycle count and CRC against the
# vector's expected.frames; and a planted wrong CRC must fail.
source "$(dirname "$0")/lib.sh"
build=${1:-build}
tb=$build/dpi/tb_vector
if [[ ! -x $tb ]]; then
    bad "no $tb (make $tb; needs verilator)"
    finish
    exit
fi
vectors=0
for dir in test-vectors/*/; do
    v=$(basename "$dir")
    [[ -f $dir/expected.frames && -f $dir/expected.stream ]] || continue
    # the VP's profile: --profile and --set of the vector's options
    read -r -a opts < <(grep -v '^#' "$dir/options" 2>/dev/null | tr '\n' ' ')
    profile=a512 sets=""
    for ((i = 0; i < ${#opts[@]}; i++)); do
        case ${opts[i]} in
            --profile) profile=${opts[++i]} ;;
            --set) sets+="${sets:+,}${opts[++i]}" ;;
        esac
    done
    out=$("$tb" +stream="$dir/expected.stream" +frames="$dir/expected.frames" +profile="$profile" \
          +sets="$sets" 2>&1)
    n=$(grep -cv '^ *$' "$dir/expected.frames")
    if [[ $out =~ ([0-9]+)\ passed,\ ([0-9]+)\ failed ]] && (( BASH_REMATCH[1] == n && BASH_REMATCH[2] == 0 )); then
        ok
    else
        bad "$v: $out"
    fi
    vectors=$((vectors + 1))
done
(( vectors >= 12 )) && ok || bad "only $vectors vectors"
# the bench catches a wrong CRC and a wrong cycle count
# (the CRC's last digit changed: 0 <-> 1, 2 <-> 3, ...)
awk 'NR == 2 {d = substr($3, 8, 1); i = index("0123456789abcdef", d) - 1;
              $3 = substr($3, 1, 7) substr("1032547698badcfe", i + 1, 1)} {print}' \
    test-vectors/builtin/expected.frames > "$tmp/crc.frames"
awk 'NR == 3 {$2 += 1} {print}' test-vectors/builtin/expected.frames > "$tmp/cyc.frames"
for f in crc cyc; do
    out=$("$tb" +stream=test-vectors/builtin/expected.stream +frames="$tmp/$f.frames" +profile=a512 2>&1)
    [[ $out =~ 3\ passed,\ 1\ failed && $out =~ FAIL:\ frame ]] && ok || bad "planted $f: $out"
done
finish
