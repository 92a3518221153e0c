#!/usr/bin/env bash
# cli-gp.sh ALBATROS — the GP's side of the command line: scenes as every
# subcommand loads them (accuracy too), the scene values the word stream
# cannot hold, screen-space scenes, and the warnings of depth and form ranges.
source "$(dirname "$0")/lib.sh"
root=$(cd "$(dirname "$0")/.." && pwd)

# accuracy loads a scene as render and reference do: OBJ with the camera options
cube=$root/test-vectors/obj-cube/scene.obj
cam=(--eye 3,2.5,4 --at 0,0,0 --up 0,1,0 --fov 45)
expect 0 'reference frame 0' "$bin" reference "$cube" --profile t32 "${cam[@]}" -o "$tmp/cube.exr"
expect 0 '^1024 pixels: .* 0 of them different$' "$bin" accuracy "$cube" --profile t32 "${cam[@]}"
expect 2 "nope\.obj: error: cannot open" "$bin" accuracy "$tmp/nope.obj" --profile t32
printf 'albatros-scene 1\nnear x\n' > "$tmp/bad.scene"
expect 2 "bad\.scene:2:6: error: expected a number, found 'x'" "$bin" accuracy "$tmp/bad.scene" --profile t32

# near and fog as the stream stores them: refused by the GP at the scene's line
printf 'albatros-scene 1\nnear %s\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n' 1e40 > "$tmp/far.scene"
for sub in gp render; do
    expect 1 "far\.scene:2:6: error: near 1e\+40 is outside .* IEEE-754 binary32" \
        "$bin" $sub "$tmp/far.scene" --profile t32 -o "$tmp/far.out"
done
expect 2 "far\.scene:2:6: error: near 1e\+40 is outside" "$bin" accuracy "$tmp/far.scene" --profile t32
[[ ! -e $tmp/far.out ]] && ok || bad "a stream or frame was written for near 1e40"
sed 's/^near 1e40$/near 3.4e38/' "$tmp/far.scene" > "$tmp/big.scene"
"$bin" gp -q "$tmp/big.scene" --profile t32 -o "$tmp/big.stream" && ok || bad "gp near 3.4e38"
expect 0 'config near=3\.39999995e\+38' "$bin" dump "$tmp/big.stream"

# aspect W/H
printf 'albatros-scene 1\nobserver aspect 4/3\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/aspect.scene"
expect 0 '"faces_out": 1' "$bin" gp --json "$tmp/aspect.scene" --profile t32

# warnings of the depth store and of the forms' exponents (docs/vp.md §4)
printf 'albatros-scene 1\nnear 1\nobserver fov 90\nobject t\n v -1 -1 0.5\n v 1 -1 0.5\n v 0 1 0.5\n f 1 2 3\nend\n' > "$tmp/sat.scene"
expect 0 "warning: frame 0: [0-9]+ samples are nearer than near=1: the depth store saturates" \
    "$bin" render "$tmp/sat.scene" --profile t32 -o "$tmp/sat.exr"
printf 'albatros-scene 1\nnear 1e-6\nobserver fov 90\nobject t\n v -100 -100 100\n v 100 -100 100\n v 0 100 100\n f 1 2 3\nend\n' > "$tmp/under.scene"
expect 0 "warning: frame 0: 512 samples are farther than near x 2\^depth_bits = 16\.7772 and are not drawn" \
    "$bin" render "$tmp/under.scene" --profile t32 -o "$tmp/under.exr"
# a plane 1e-300 from the eye: depth form 1e300, beyond the exponent range
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 1e-300 1\n v 0 1e-300 3\n v 1 1e-300 1\n f 1 2 3\nend\n' > "$tmp/edge.scene"
# the warning names the face's line, the form and its likely cause
expect 0 "edge.scene:7: warning: frame 0: the face's depth form exceeds the exponent range .*nearly edge-on.*1 face in all" \
    "$bin" render "$tmp/edge.scene" --profile t32 -o "$tmp/edge.exr"
expect 0 "edge.scene:7: warning: frame 0: the face's depth form exceeds" \
    "$bin" gp "$tmp/edge.scene" --profile t32 -o "$tmp/edge.stream"
# huge intensities are not an edge-on face: the intensity form is named
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5 i 1e300\n v 1 -1 5 i 0\n v 0 1 5 i 0\n f 1 2 3\nend\n' > "$tmp/inten.scene"
expect 0 "inten.scene:7: warning: frame 0: the face's intensity form exceeds .*intensities are too large" \
    "$bin" render "$tmp/inten.scene" --profile t32 -o "$tmp/inten.exr"

# screen space: near/Z = near x depth / largest depth; the largest depth
# saturates the store at the default near 1, and a written near is kept
printf 'albatros-scene 1\nscreenspace\nobject a\n v 2 2 10\n v 30 2 10\n v 16 30 10\n f 1 2 3\nend\nobject b\n v 0 0 5\n v 32 0 5\n v 32 32 5\n v 0 32 5\n f 1 2 3 4\nend\n' > "$tmp/ss.scene"
expect 0 "warning: frame 0: [0-9]+ samples are nearer than near=1: .*lower 'near' in the scene" \
    "$bin" render "$tmp/ss.scene" --profile t32 -o "$tmp/ss.exr"
sed 's/^screenspace$/screenspace\nnear 0.5/' "$tmp/ss.scene" > "$tmp/ss-near.scene"
out=$("$bin" render "$tmp/ss-near.scene" --profile t32 -o "$tmp/ss-near.exr" 2>&1)
[[ $? -eq 0 && $out != *warning* && $out == *"1024 samples written"* ]] && ok || bad "screenspace near 0.5: $out"
expect 0 '^1024 pixels: .* 0 of them different$' "$bin" accuracy "$tmp/ss-near.scene" --profile t32

finish
