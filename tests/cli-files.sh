#!/usr/bin/env bash
# cli-files.sh ALBATROS — files a user can trust (docs/files.md): no output
# ever removes a path or leaves a part of a file under a good one's name,
# two outputs (or an output and an input) never share a file, every failed
# write — stdout's included — is an error, and no input that is not a
# regular file hangs the run or eats memory.
source "$(dirname "$0")/lib.sh"
bin=$(realpath "$bin")   # some runs below start in $tmp

printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5\n v 1 -1 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/one.scene"
{ cat "$tmp/one.scene"; printf 'frame\nframe\n'; } > "$tmp/two.scene"
"$bin" gp "$tmp/one.scene" -q -o "$tmp/one.stream" || bad "gp one.scene"
"$bin" gp "$tmp/two.scene" -q -o "$tmp/two.stream" || bad "gp two.scene"
no_temps() { ! compgen -G "$1/.*.tmp" > /dev/null; }

# ---- 1. a failed write removes nothing, a device least of all ----
# a symbolic link to /dev/full fails every write; as root, a real node too
ln -s /dev/full "$tmp/full"
devs=("$tmp/full")
if [[ $(id -u) -eq 0 ]] && mknod "$tmp/fullnode" c 1 7 2>/dev/null; then devs+=("$tmp/fullnode"); fi
for dev in "${devs[@]}"; do
    for args in "render $tmp/one.scene -o DEV" "render $tmp/one.scene --png DEV" \
                "render $tmp/one.scene --view depth:DEV" "vp $tmp/one.stream -o DEV" \
                "gp $tmp/one.scene -o DEV" "gp $tmp/one.scene --memh DEV" "gp $tmp/one.scene --hex DEV" \
                "render $tmp/one.scene --json --stream DEV" "scene random -o DEV --seed 2" \
                "render $tmp/one.scene --fidelity cycle --vcd DEV" \
                "render $tmp/one.scene --fidelity cycle --events DEV" \
                "render $tmp/one.scene --dump DEV"; do
        # shellcheck disable=SC2086
        q=-q; [[ $args == scene* ]] && q=
        out=$("$bin" ${args//DEV/$dev} $q 2>&1 >/dev/null); rc=$?
        [[ $rc -eq 1 && $out == *"No space left on device"* && ( -c $dev || -L $dev ) ]] && ok ||
            bad "$args to ${dev##*/}: exit $rc, $( [[ -e $dev || -L $dev ]] && echo kept || echo REMOVED): $out"
    done
done
[[ -L $tmp/full && $(readlink "$tmp/full") == /dev/full ]] && ok || bad "the link to /dev/full was replaced"
# a device that takes the bytes gets them: the EXR through a FIFO (no pwrite
# there: built in memory, written in one go) is the file's bytes
"$bin" render "$tmp/one.scene" -q -o "$tmp/ref.exr"
mkfifo "$tmp/pipe"
cat "$tmp/pipe" > "$tmp/via-fifo.exr" &
"$bin" render "$tmp/one.scene" -q -o "$tmp/pipe" && wait $! && cmp -s "$tmp/ref.exr" "$tmp/via-fifo.exr" &&
    [[ -p $tmp/pipe ]] && ok || bad "EXR through a FIFO differs from the file"

# ---- 2. writes are atomic: a full disk keeps the old file ----
"$bin" scene random --faces 3000 --seed 5 -o "$tmp/many.scene"
"$bin" render "$tmp/one.scene" --profile a1024 -q -o "$tmp/big.exr" --png "$tmp/big.png" --stream "$tmp/big.stream"
cp "$tmp/big.exr" "$tmp/big.exr.old"; cp "$tmp/big.png" "$tmp/big.png.old"
# the old files are from another run: anything new under the names shows
"$bin" render "$tmp/one.scene" -q --profile a256 -o "$tmp/other.exr"
for what in "-o $tmp/big.exr" "--png $tmp/big.png"; do
    # shellcheck disable=SC2086
    out=$( (ulimit -f 16; "$bin" render "$tmp/many.scene" --profile a1024 -q $what) 2>&1); rc=$?
    [[ $rc -eq 1 && $out == *"File too large"* ]] && cmp -s "$tmp/big.exr" "$tmp/big.exr.old" &&
        cmp -s "$tmp/big.png" "$tmp/big.png.old" && no_temps "$tmp" && ok ||
        bad "ulimit -f 16, $what: exit $rc, old file $(cmp -s "$tmp/big.exr" "$tmp/big.exr.old" && echo kept || echo LOST): $out"
done
cp "$tmp/big.stream" "$tmp/big.stream.old"
out=$( (ulimit -f 16; "$bin" gp "$tmp/many.scene" -q -o "$tmp/big.stream") 2>&1); rc=$?
[[ $rc -eq 1 ]] && cmp -s "$tmp/big.stream" "$tmp/big.stream.old" && no_temps "$tmp" && ok || bad "gp -o over the limit: exit $rc: $out"
out=$( (ulimit -f 16; "$bin" render "$tmp/many.scene" -q --json --stream "$tmp/big.stream") 2>&1 >/dev/null); rc=$?
[[ $rc -eq 1 ]] && cmp -s "$tmp/big.stream" "$tmp/big.stream.old" && no_temps "$tmp" && ok || bad "--stream over the limit: exit $rc: $out"
# kill -9 while a large frame is written: the old file, or the whole new one
"$bin" render "$tmp/one.scene" --size 2048x2048 -q -o "$tmp/kill.exr" && cp "$tmp/kill.exr" "$tmp/kill.new"
cp "$tmp/other.exr" "$tmp/kill.exr"
"$bin" render "$tmp/one.scene" --size 2048x2048 -q -o "$tmp/kill.exr" &
pid=$!
for ((i = 0; i < 2000; i++)); do compgen -G "$tmp/.kill.exr.*.tmp" > /dev/null && break; sleep 0.01; done
kill -9 $pid; wait $pid 2>/dev/null
cmp -s "$tmp/kill.exr" "$tmp/other.exr" || cmp -s "$tmp/kill.exr" "$tmp/kill.new" && ok ||
    bad "kill -9 during the write left neither the old nor the new frame"
rm -f "$tmp"/.kill.exr.*.tmp   # what kill -9 leaves: a temporary beside it, never the name
# Ctrl-C (SIGINT) during the write: the old file, and no temporary file left
cp "$tmp/other.exr" "$tmp/kill.exr"
"$bin" render "$tmp/one.scene" --size 2048x2048 -q -o "$tmp/kill.exr" &
pid=$!
for ((i = 0; i < 2000; i++)); do compgen -G "$tmp/.kill.exr.*.tmp" > /dev/null && break; sleep 0.01; done
kill -INT $pid; wait $pid; rc=$?
{ [[ $rc -eq 130 ]] && cmp -s "$tmp/kill.exr" "$tmp/other.exr" || cmp -s "$tmp/kill.exr" "$tmp/kill.new"; } &&
    no_temps "$tmp" && ok || bad "SIGINT during the write: exit $rc, temporaries: $(ls -a "$tmp" | grep tmp)"
# the mode of the file replaced is kept
chmod 640 "$tmp/big.exr"
"$bin" render "$tmp/one.scene" -q -o "$tmp/big.exr" && [[ $(stat -c %a "$tmp/big.exr") == 640 ]] && ok ||
    bad "mode not kept: $(stat -c %a "$tmp/big.exr")"
# a read-only file is not replaced (the old open would have failed too)
if [[ $(id -u) -ne 0 ]]; then
    chmod 444 "$tmp/big.exr"
    expect 1 "cannot write: Permission denied" "$bin" render "$tmp/one.scene" -q -o "$tmp/big.exr"
    chmod 644 "$tmp/big.exr"
fi

# ---- 3. long paths are written whole (or refused), never cut short ----
long=$(printf './%.0s' {1..505})abcdefghijklmnopqrstuvwxyz
(cd "$tmp" && "$bin" render one.scene -q -o "$long.exr" --png "$long.png") &&
    exrheader "$tmp/abcdefghijklmnopqrstuvwxyz.exr" > /dev/null 2>&1 &&
    file_ok=$(head -c 4 "$tmp/abcdefghijklmnopqrstuvwxyz.png" | od -An -c | tr -d ' ') &&
    [[ $file_ok == 211PNG && ! -e $tmp/abcdefghijklm ]] && ok || bad "a 1040-character -o was cut short"
# numbered frames of a long name
(cd "$tmp" && "$bin" render two.scene -q -o "$long.exr") && [[ -s $tmp/abcdefghijklmnopqrstuvwxyz.0001.exr ]] &&
    ok || bad "numbered frames of a long name"
toolong=$tmp/$(printf 'd%.0s' {1..300})/x.exr
expect 1 "File name too long" "$bin" render "$tmp/one.scene" -q -o "$toolong"

# ---- 4. two outputs, or an output and an input, are never one file ----
cp "$tmp/one.scene" "$tmp/s.scene"; cp "$tmp/s.scene" "$tmp/s.scene.old"
expect 2 "-o .*s.scene is the input .*s.scene: refusing to overwrite it" "$bin" gp "$tmp/s.scene" -o "$tmp/s.scene"
expect 2 "is the input" "$bin" gp "$tmp/s.scene" -o "$tmp/./s.scene"
ln -s s.scene "$tmp/link.scene"
expect 2 "is the input" "$bin" gp "$tmp/link.scene" -o "$tmp/s.scene"
expect 2 "is the input" "$bin" gp "$tmp/s.scene" --memh "$tmp/link.scene"
cmp -s "$tmp/s.scene" "$tmp/s.scene.old" && [[ -L $tmp/link.scene ]] && ok || bad "the input was overwritten"
expect 2 "is the input" "$bin" vp "$tmp/one.stream" -o "$tmp/x.exr" --dump "$tmp/one.stream"
rm -f "$tmp/x.exr"
expect 2 "--dump .*x.exr and -o .*x.exr are the same file" "$bin" render "$tmp/one.scene" -o "$tmp/x.exr" --dump "$tmp/x.exr"
mkdir "$tmp/sub"
expect 2 "are the same file" "$bin" render "$tmp/one.scene" -o "$tmp/x.exr" --dump "$tmp/sub/../x.exr"
expect 2 "--view depth .*v.png and --png .*v.png are the same file" "$bin" render "$tmp/one.scene" --png "$tmp/v.png" --view "depth:$tmp/./v.png"
expect 2 "are the same file" "$bin" render "$tmp/two.scene" --png "$tmp/v.png" --view "level:$tmp/v.png"
[[ ! -e $tmp/x.exr && ! -e $tmp/v.0000.png ]] && ok || bad "a refused run wrote files"
expect 2 "-o .*x.png: -o writes OpenEXR, but the name ends in .png" "$bin" render "$tmp/one.scene" -o "$tmp/x.png"
expect 2 "--png .*x.EXR: --png writes PNG, but the name ends in .exr" "$bin" render "$tmp/one.scene" --png "$tmp/x.EXR"
expect 2 "--view depth .*d.exr: --view depth writes PNG" "$bin" render "$tmp/one.scene" --view "depth:$tmp/d.exr"
# a texture the scene reads
printf '\x89PNG' > /dev/null
"$bin" render "$tmp/one.scene" -q --png "$tmp/tex.png"
printf 'albatros-scene 1\ntexture t file tex.png\nobject o\n v -1 -1 5 t 0 0\n v 1 -1 5 t 1 0\n v 0 1 5 t 0 1\n texture t\n f 1 2 3\nend\n' > "$tmp/tex.scene"
expect 2 "--png .*tex.png is the input .*tex.png" "$bin" render "$tmp/tex.scene" --png "$tmp/tex.png"
# a stream whose two frames have one number: both would go to f.0000.*
python3 - "$tmp/two.stream" "$tmp/dup.stream" <<'EOF'
import struct, sys
w = list(struct.unpack('<%dI' % (len(open(sys.argv[1], 'rb').read()) // 4), open(sys.argv[1], 'rb').read()))
w[w.index(0xF0000001)] = 0xF0000000       # frame 1 renumbered 0
open(sys.argv[2], 'wb').write(struct.pack('<%dI' % len(w), *w))
EOF
expect 2 "two frames of the stream have number 0: both would be written to .*f.0000.exr" \
    "$bin" vp "$tmp/dup.stream" -o "$tmp/f.exr"
[[ ! -e $tmp/f.0000.exr ]] && ok || bad "frames written before the refusal"
expect 0 "" "$bin" vp "$tmp/dup.stream" --json   # nothing numbered: nothing to refuse
# /dev/null takes any number of outputs
expect 0 "" "$bin" render "$tmp/two.scene" -q -o /dev/null --png /dev/null --view depth:/dev/null

# ---- 5. a failed write to stdout is an error ----
for args in "dump $tmp/one.stream" "gp $tmp/one.scene --json" "gp $tmp/one.scene --hex -" \
            "gp $tmp/one.scene --memh -" "render $tmp/one.scene --json" "profiles" \
            "scene random" "compare $tmp/ref.exr $tmp/ref.exr" "--version" "gp --version" \
            "render $tmp/one.scene --fidelity cycle --events -"; do
    # shellcheck disable=SC2086
    out=$("$bin" $args 2>&1 > /dev/full); rc=$?
    want=1; [[ $args == compare* ]] && want=2
    [[ $rc -eq $want && $out == *"stdout"*"write error: No space left on device"* ]] && ok ||
        bad "$args > /dev/full: exit $rc (expected $want): $out"
done
# a reader that went away, with SIGPIPE ignored: EPIPE is an error too
python3 - "$bin" "$tmp/many.scene" <<'EOF' && ok || bad "EPIPE on stdout ignored"
import os, signal, subprocess, sys
signal.signal(signal.SIGPIPE, signal.SIG_IGN)     # inherited: the child ignores it too
r, w = os.pipe()
os.close(r)                                        # nobody will read
p = subprocess.run([sys.argv[1], 'gp', sys.argv[2], '--hex', '-'], stdout=w,
                   stderr=subprocess.PIPE, restore_signals=False)
os.close(w)
err = p.stderr.decode()
sys.exit(0 if p.returncode == 1 and 'Broken pipe' in err else
         print('exit %d: %s' % (p.returncode, err)) or 1)
EOF

# ---- 6. inputs that are not regular files neither hang nor eat memory ----
mkfifo "$tmp/tex.fifo" "$tmp/mtl.fifo"
printf 'albatros-scene 1\ntexture t file tex.fifo\nobject o\n v 0 0 5\nend\n' > "$tmp/fifo.scene"
expect 1 "tex.fifo': is a FIFO, not a regular file" timeout 20 "$bin" gp "$tmp/fifo.scene" --json
printf 'mtllib mtl.fifo\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/fifo.obj"
expect 0 "material library .*mtl.fifo': cannot open: is a FIFO, not a regular file" timeout 20 "$bin" gp "$tmp/fifo.obj" --json
printf 'mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/zero.obj"
expect 0 "material library '/dev/zero': cannot open: is a character device" timeout 20 "$bin" gp "$tmp/zero.obj" --json
# /dev/zero as a scene, an OBJ or a stream: refused at its first byte, at
# once and in little memory (peak resident size under 100 MB, where reading
# it whole would take all there is)
small() {   # small STATUS PATTERN ARGS...: the run's status, message and peak memory
    local want=$1 pat=$2; shift 2
    local out
    out=$(python3 - "$bin" "$@" <<'PYEOF'
import resource, subprocess, sys
try:
    p = subprocess.run(sys.argv[1:], capture_output=True, timeout=20)
    rc, err = p.returncode, p.stderr.decode(errors='replace')
except subprocess.TimeoutExpired:
    rc, err = 'timeout', ''
print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, err.replace('\n', ' '))
PYEOF
)
    read -r rc kb msg <<<"$out"
    [[ $rc == "$want" && $kb -lt 100000 ]] && grep -qE -- "$pat" <<<"$msg" && ok ||
        bad "$*: exit $rc, peak $kb KB: $msg"
}
small 1 "/dev/zero:1:1: error: byte 0x00" gp /dev/zero --json
ln -s /dev/zero "$tmp/zero-link.obj"
small 1 "zero-link.obj:1:1: error: byte 0x00" gp "$tmp/zero-link.obj" --json
small 1 "/dev/zero: offset 0: error: word 0: 0x00000000 is not a packet opcode \\(expected CONFIG\\)" vp /dev/zero --json
small 1 "/dev/urandom: offset 0: error: word 0" dump /dev/urandom
# a pipe as the scene is read like a file (process substitution)
expect 0 '"faces_out": 1' "$bin" gp <(cat "$tmp/one.scene") --json
expect 1 "is a directory" "$bin" gp "$tmp" --json

finish
