#!/usr/bin/env bash
# sweep-cycles.sh ALBATROS OUT SCENE_DIR PROFILE [--set k=v ...] — the cycle
# side of one point of the design-space view (docs/fpga.md, make fpga-sweep):
# the cycle model's cycles per frame (the mean over a run's frames, a half rounded up)
# for the built-in scene and the stress scenes in SCENE_DIR (NAME.scene).
# Writes OUT (one line): builtin=N NAME=N ...
set -euo pipefail
bin=$1 out=$2 scenes=$3 profile=$4; shift 4
cycles() {   # [SCENE]
    local json
    json=$("$bin" render "$@" --profile "$profile" "${sets[@]}" --fidelity cycle --json \
           2> "$out.err") || {
        echo "sweep-cycles.sh: albatros render $* --profile $profile ${sets[*]} failed:" >&2
        cat "$out.err" >&2
        return 1; }
    python3 -c 'import json,sys
f = json.loads(sys.stdin.read())["frames"]
assert f, "no frames"
s, n = sum(x["timing"]["cycles"] for x in f), len(f)
print((2 * s + n) // (2 * n))   # the mean, a half rounded up' <<< "$json"
}
sets=("$@")
line="builtin=$(cycles)"
for s in "$scenes"/*.scene; do
    line="$line $(basename "$s" .scene)=$(cycles "$s")"
done
echo "$line" > "$out.tmp"
mv "$out.tmp" "$out"
rm -f "$out.err"
