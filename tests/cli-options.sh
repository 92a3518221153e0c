#!/usr/bin/env bash
# cli-options.sh ALBATROS — how options are read: --set/--size whatever their
# place around --profile, unknown and misplaced options as errors (vectors,
# scene, stability), the help that lists them, and the VCD declarations in
# the order docs/microarchitecture.md's table gives (t32 runs only).
source "$(dirname "$0")/lib.sh"
root=$(cd "$(dirname "$0")/.." && pwd)

# --set and --size before --profile are not dropped (docs/profiles.md)
json() { "$bin" render --json -q "$@" 2>&1; }
levels() { json "$@" | grep -m1 -o '"cells_per_level": \[[^]]*\]' | tr -cd , | wc -c; }
[[ $(levels --set aa=1 --profile t32) -eq 6 ]] && ok || bad "--set aa=1 before --profile t32: not 7 levels"
[[ $(json --set aa=1 --profile t32) == "$(json --profile t32 --set aa=1)" ]] && ok || bad "--set order changes the render"
[[ $(json --size 64x64 --profile t32) == "$(json --profile t32 --size 64x64)" &&
   $(json --size 64x64 --profile t32) != "$(json --profile t32)" ]] && ok || bad "--size before --profile dropped"
# a later --set of the same key wins, wherever --profile stands
[[ $(json --set aa=2 --profile t32 --set aa=1) == "$(json --profile t32 --set aa=1)" ]] && ok || bad "later --set aa=1 lost"
[[ $(levels --set aa=1 --profile t32 --set aa=0) -eq 5 ]] && ok || bad "later --set aa=0 lost"
# every subcommand with the common options: method checks the aa it was given
expect 2 "aa=0" "$bin" method zbuffer --set aa=1 --profile t32 -o "$tmp/m.exr"
expect 2 "unknown profile key" "$bin" gp --json --set nope=1 --profile t32

# vectors: options anywhere, unknown ones exit 2; an options file in any order
mkdir -p "$tmp/v/tri"
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/v/tri/scene.scene"
echo "a triangle" > "$tmp/v/tri/README"
echo "--profile t32 --set aa=1" > "$tmp/v/tri/options"
expect 0 "created tri" "$bin" vectors bless "$tmp/v"
echo "--set aa=1 --profile t32" > "$tmp/v/tri/options"
expect 0 "1 passed, 0 failed" "$bin" vectors check "$tmp/v" --diff-dir "$tmp/d"
expect 2 "albatros vectors: unknown option '--bogus'" "$bin" vectors check --bogus "$tmp/v"
expect 2 "unknown option '--bogus'" "$bin" vectors check "$tmp/v" tri --bogus
expect 2 "option '--diff-dir' needs a value" "$bin" vectors check "$tmp/v" --diff-dir
expect 2 "--diff-dir is for check" "$bin" vectors bless "$tmp/v" --diff-dir "$tmp/d"
expect 2 "unknown action 'frob'" "$bin" vectors frob "$tmp/v"
expect 0 "usage: albatros vectors check \[--diff-dir DIR\]" "$bin" vectors --help
sed -i 's/^ f 1 2 3$/ f 1 2 3 colour 10 20 30/' "$tmp/v/tri/scene.scene"
expect 1 "diff image $tmp/d/tri.0000.png" "$bin" vectors check "$tmp/v" tri --diff-dir "$tmp/d"
[[ -s $tmp/d/tri.0000.png ]] && ok || bad "--diff-dir after the names: no diff image"

# reference --help lists the options it takes
expect 0 "  --json " "$bin" reference --help
expect 0 "  -q, --quiet " "$bin" reference --help

# scene: an option of another generator is an error naming both
expect 2 "albatros scene: slivers: --faces is for random only" "$bin" scene slivers --faces 3
expect 2 "slivers: --flat is for random only" "$bin" scene --flat slivers
expect 2 "random: --per-angle is for slivers only" "$bin" scene random --per-angle 2
expect 2 "cyclic: --size is for random only" "$bin" scene cyclic --severity 1 --size 0.5
expect 0 "" "$bin" scene random --faces 3 --flat --size 0.2 --seed 4 -o "$tmp/r.scene"
expect 0 "" "$bin" scene slivers --per-angle 1 --seed 4 -o "$tmp/s.scene"
# scene random --behind/--backfacing: the fractions of faces crossing Z = 0
# and wound away (the bench's scenes have neither: both renderers draw them all)
"$bin" scene random --faces 40 --seed 7 --behind 0 --backfacing 0 -o "$tmp/front.scene"
expect 0 "faces: 40 in, 40 out; dropped 0 behind, 0 back-facing" "$bin" gp "$tmp/front.scene" -o "$tmp/front.stream"
"$bin" scene random --faces 40 --seed 7 --backfacing 1 -o "$tmp/back.scene"
expect 0 "faces: 40 in, 0 out; dropped 0 behind, 40 back-facing" "$bin" gp "$tmp/back.scene" -o "$tmp/back.stream"
"$bin" scene random --faces 40 --seed 7 -o "$tmp/default.scene"
expect 0 "faces: 40 in, 30 out; dropped 0 behind, 8 back-facing" "$bin" gp "$tmp/default.scene" -o "$tmp/default.stream"
expect 2 "--behind 1.5: expected a fraction in \[0, 1\]" "$bin" scene random --behind 1.5
expect 2 "--backfacing x: expected a fraction" "$bin" scene random --backfacing x
expect 2 "slivers: --behind is for random only" "$bin" scene slivers --behind 0

# stability --jobs: with --family, only those jobs; the speed job with --speed
"$bin" stability --jobs --family cyclic --out "$tmp/st" > "$tmp/jobs1.txt"
[[ $(wc -l < "$tmp/jobs1.txt") -eq 1 ]] && grep -q -- '--family cyclic$' "$tmp/jobs1.txt" \
    && ok || bad "--jobs --family cyclic: $(cat "$tmp/jobs1.txt")"
"$bin" stability --jobs --speed --family far --family cyclic --out "$tmp/st" > "$tmp/jobs2.txt"
[[ $(wc -l < "$tmp/jobs2.txt") -eq 3 && $(sed -n 1p "$tmp/jobs2.txt") == *"--family far" &&
   $(sed -n 2p "$tmp/jobs2.txt") == *"--family cyclic" && $(sed -n 3p "$tmp/jobs2.txt") == *"--speed" ]] \
    && ok || bad "--jobs --speed --family far --family cyclic: $(cat "$tmp/jobs2.txt")"
[[ $("$bin" stability --jobs --speed | wc -l) -eq 1 && $("$bin" stability --jobs | wc -l) -eq 11 ]] \
    && ok || bad "--jobs --speed / --jobs: wrong number of jobs"
expect 2 "albatros stability: --eye: the stress scenes set their own observer" "$bin" stability --jobs --eye 1,2,3
expect 2 "stability: --fov" "$bin" stability --family cyclic --fov 30 --out "$tmp/st"

# the VCD declares every scope's signals in the order of the doc's table
"$bin" render --profile t32 --fidelity cycle -q --vcd "$tmp/x.vcd" --vcd-window 0:0 && ok || bad "cycle run with --vcd failed"
awk '/^\$scope/ { scope[++d] = $3 } /^\$upscope/ { d-- } /^\$var/ { print scope[d] "." $5 }' \
    "$tmp/x.vcd" > "$tmp/vcd.txt"
awk -F'|' '/^## Traces/ { on = 1 } on && /^\| scope \| signal/ { table = 1; next }
           table && !/^\|/ { exit }
           table && !/^\|---/ { gsub(/[` ]/, "", $2); gsub(/[` ]/, "", $3)
                               if ($2 != "") scope = $2
                               n = split($3, s, ","); for (i = 1; i <= n; i++) print scope "." s[i] }' \
    "$root/docs/microarchitecture.md" > "$tmp/doc.txt"
[[ $(wc -l < "$tmp/doc.txt") -ge 20 ]] && cmp -s "$tmp/doc.txt" "$tmp/vcd.txt" \
    && ok || bad "VCD declarations differ from the Traces table: $(diff "$tmp/doc.txt" "$tmp/vcd.txt" | tr '\n' ' ')"

finish
