#!/usr/bin/env bash
# cli-json.sh ALBATROS — every --json output is a JSON document a real
# parser (Python's json module) accepts, including paths with quotes,
# backslashes, control characters and bytes that are not UTF-8, and
# frames whose PSNR is infinite; the values parsed are the ones the text
# output gives.
source "$(dirname "$0")/lib.sh"
bin=$(realpath "$bin")

# json FILE [KEY...]: parse FILE strictly (no NaN/Infinity), print the value at
# the keys (a path: frames.0.frame)
json() {
    python3 - "$@" <<'EOF'
import json, sys
def strict(c):
    raise ValueError('not JSON: ' + c)
v = json.load(open(sys.argv[1], encoding='utf-8', errors='strict'), parse_constant=strict)
for k in sys.argv[2:]:
    v = v[int(k)] if isinstance(v, list) else v[k]
print(v if not isinstance(v, (dict, list)) else json.dumps(v))
EOF
}
# parses CMD...: the command's stdout is one JSON document (exit 0, or 1
# when $status1 is set: compare's "they differ")
parses() {
    local out="$tmp/out.json" rc
    "$@" > "$out" 2> "$tmp/err"; rc=$?
    if [[ $rc -ne 0 && ! ( $rc -eq 1 && -n ${status1:-} ) ]]; then bad "$*: exit $rc: $(cat "$tmp/err")"; return; fi
    json "$out" > /dev/null 2> "$tmp/perr" && ok || bad "$*: not JSON: $(tail -1 "$tmp/perr"): $(head -c 300 "$out")"
}

printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5\n v 1 -1 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/one.scene"
{ cat "$tmp/one.scene"; printf 'frame\nframe\n'; } > "$tmp/two.scene"
"$bin" gp "$tmp/two.scene" -q -o "$tmp/two.stream"
"$bin" render "$tmp/two.scene" -q -o "$tmp/a.exr"
sed 's/ v 0 1 5/ v 0.5 1 5/' "$tmp/two.scene" > "$tmp/moved.scene"
"$bin" render "$tmp/moved.scene" -q -o "$tmp/r.exr"

# every command with --json
parses "$bin" gp "$tmp/two.scene" --json
parses "$bin" gp --json
for fid in functional timed cycle; do
    parses "$bin" render "$tmp/two.scene" --json -q --fidelity $fid
    parses "$bin" vp "$tmp/two.stream" --json -q --fidelity $fid
done
parses "$bin" reference "$tmp/two.scene" --json -q
parses "$bin" compare "$tmp/a.0000.exr" "$tmp/a.0000.exr" --json      # PSNR infinite
status1=1 parses "$bin" compare "$tmp/a.exr" "$tmp/r.exr" --json      # numbered runs, differing
[[ $(json "$tmp/out.json" frames 0 first_diff channel) =~ ^[a-z.]+$ ]] && ok || bad "compare first_diff"
parses "$bin" accuracy "$tmp/one.scene" --profile a256 --json
parses "$bin" stream --sim --profile t32 "$tmp/two.scene" --json
parses "$bin" stream --sim --frames --profile t32 "$tmp/two.scene" --json
parses "$bin" board list --sim --json
parses "$bin" board info --sim --json
parses "$bin" board reset --sim --json
# a stream the board gets wrong: the report's problem strings are JSON strings
"$bin" stream --sim --profile t32 "$tmp/two.scene" --fault flip=0 --json > "$tmp/out.json"
[[ $? -eq 1 ]] && json "$tmp/out.json" first_problem > /dev/null && ok || bad "stream --fault flip: $(cat "$tmp/out.json")"

# the values: JSON's faces and words are what the text summary says
"$bin" gp "$tmp/two.scene" --json > "$tmp/out.json"
words=$("$bin" gp "$tmp/two.scene" -o /dev/null 2>&1 | sed -n 's/^  words: //p')
[[ $(json "$tmp/out.json" totals words) == "$words" && $(json "$tmp/out.json" frames) == 2 ]] && ok ||
    bad "gp --json words $(json "$tmp/out.json" totals words), text $words"
"$bin" render "$tmp/two.scene" --json -q --fidelity cycle > "$tmp/out.json"
[[ $(json "$tmp/out.json" frames 1 frame) == 1 && $(json "$tmp/out.json" frames 0 timing realtime_50hz) == True ]] &&
    ok || bad "render --json frames: $(head -c 300 "$tmp/out.json")"

# names no JSON writer by hand gets right: quotes, backslashes, control
# characters, bytes that are not UTF-8 (written as U+FFFD), and UTF-8 kept
mkdir -p "$tmp/names"
names=('q"uote' 'back\slash' $'tab\there' $'new\nline' $'bell\x07' $'latin1-\xe9' $'utf8-\xc3\xa9' $'half-\xe2\x82')
for n in "${names[@]}"; do
    cp "$tmp/one.scene" "$tmp/names/$n.scene"
    "$bin" gp "$tmp/names/$n.scene" --json > "$tmp/out.json" 2> "$tmp/err" || { bad "gp on '$n': $(cat "$tmp/err")"; continue; }
    got=$(json "$tmp/out.json" scene 2> "$tmp/perr") || { bad "'$n': not JSON: $(cat "$tmp/perr"): $(cat "$tmp/out.json")"; continue; }
    want=$(python3 -c 'import sys; print(sys.argv[1].encode("utf-8", "surrogateescape").decode("utf-8", "replace"))' "$tmp/names/$n.scene")
    [[ $got == "$want" ]] && ok || bad "'$n': scene name decoded as '$got', expected '$want'"
done

finish
