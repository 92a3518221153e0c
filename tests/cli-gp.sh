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
expect 0 '^judged [0-9]+ of 1024 pixels .*: 0 errors$' "$bin" accuracy "$cube" --profile t32 "${cam[@]}"
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
expect 0 "warning: frame 0: [0-9]+ samples are nearer than near=1: .*lower near \('near' in .*ss\.scene or --near D; now 1\)" \
    "$bin" render "$tmp/ss.scene" --profile t32 -o "$tmp/ss.exr"
sed 's/^screenspace$/screenspace\nnear 0.5/' "$tmp/ss.scene" > "$tmp/ss-near.scene"
out=$("$bin" render "$tmp/ss-near.scene" --profile t32 -o "$tmp/ss-near.exr" 2>&1)
[[ $? -eq 0 && $out != *warning* && $out == *"1024 samples written"* ]] && ok || bad "screenspace near 0.5: $out"
expect 0 '^judged [0-9]+ of 1024 pixels .*: 0 errors$' "$bin" accuracy "$tmp/ss-near.scene" --profile t32

# depth precision (docs/vp.md, section 4): a quad 0.2% behind a triangle at
# Z = 10^4 with near 0.1 falls into the triangle's depth step; the warning
# names the faces, the step and both fixes, and --near removes the tie
printf 'albatros-scene 1\nobserver fov 60\nobject quad\n v -4000 -4000 10020\n v 4000 -4000 10020\n v 4000 4000 10020\n v -4000 4000 10020\n f 1 2 3 4\nend\nobject tri\n v -3000 -3000 10000\n v 3000 -3000 10000\n v 0 3000 10000\n f 1 2 3\nend\n' > "$tmp/tie.scene"
expect 0 "warning: frame 0: 35378 samples where two faces fell into one depth step, .*faces 0 \(kept\) and 1 at pixel \(255, 124\), depth 167 of 2\^24, Z = 1e\+04, where one step is 60\.2 in Z; raise depth_bits \(--set depth_bits=32: a step of 0\.235 there\) or near \('near' in .*tie\.scene or --near D; now 0\.1\): the nearest surface is at Z = 1e\+04, so near up to 9e\+03 keeps it" \
    "$bin" render "$tmp/tie.scene" -o "$tmp/tie.exr"
out=$("$bin" render "$tmp/tie.scene" -o "$tmp/tie.exr" --near 5000 2>&1)
[[ $? -eq 0 && $out != *warning* && $out == *"160694 samples written"* ]] && ok || bad "tie scene --near 5000: $out"
out=$("$bin" render "$tmp/tie.scene" -o "$tmp/tie.exr" --set depth_bits=32 2>&1)
[[ $? -eq 0 && $out != *warning* ]] && ok || bad "tie scene depth_bits=32: $out"
# the stream alone: the fix is the GP's
"$bin" gp "$tmp/tie.scene" -o "$tmp/tie.stream" >/dev/null 2>&1
expect 0 "one depth step.*or near \(the GP's --near D, then a new stream\)" "$bin" vp "$tmp/tie.stream" -o "$tmp/tie.exr"
# near for OBJ (docs/scene-format.md): a triangle 6 cm from the eye in front
# of a quad 9 cm from it: both nearer than the default near 0.1, so they tie
# and the quad, drawn first, hides the triangle; --near 0.01 draws it
printf 'v -0.05 -0.05 4.91\nv 0.05 -0.05 4.91\nv 0.05 0.05 4.91\nv -0.05 0.05 4.91\nv -0.02 -0.02 4.94\nv 0.02 -0.02 4.94\nv 0 0.02 4.94\nf 1 2 3 4\nf 5 6 7\n' > "$tmp/near.obj"
expect 0 "warning: frame 0: 71468 samples are nearer than near=0\.1: .*lower near \(--near D; now 0\.1\)" \
    "$bin" render "$tmp/near.obj" --profile a256 -o "$tmp/near.exr"
expect 1 "near-clamp +60516 pixels .* 10952 differ +judged" "$bin" accuracy "$tmp/near.obj" --profile a256
expect 0 "judged 65536 of 65536 pixels .*: 0 errors" "$bin" accuracy "$tmp/near.obj" --profile a256 --near 0.01
out=$("$bin" render "$tmp/near.obj" --profile a256 -o "$tmp/near.exr" --near 0.01 2>&1)
[[ $? -eq 0 && $out != *warning* && $out == *"71468 samples written"* ]] && ok || bad "OBJ --near 0.01: $out"
expect 2 "--near 0: expected a distance in 1\.17549e-38 \.\. 3\.40282e\+38" "$bin" gp "$tmp/near.obj" --near 0
expect 2 "--near 1e40: expected a distance" "$bin" render "$tmp/near.obj" --near 1e40 -o "$tmp/x.exr"
expect 2 "--near x: expected a distance" "$bin" accuracy "$tmp/near.obj" --near x
expect 2 "--set near=0.5: near is the scene's depth scale, not a profile field: use --near 0.5" "$bin" gp "$tmp/near.obj" --set near=0.5
# --near replaces a scene's near too: the stream's CONFIG word holds it
"$bin" gp "$tmp/tie.scene" --near 0.25 -o "$tmp/n25.stream" >/dev/null 2>&1
expect 0 "near=0\.25" "$bin" dump "$tmp/n25.stream"

# extreme cameras are cameras (issue 16, item 10): a denormal --up is the
# direction it points, an eye at 1e308 is no "coincident" eye and at
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/cam.obj"
"$bin" gp "$tmp/cam.obj" --up 1e-320,0,0 -q -o "$tmp/tiny.stream" && "$bin" gp "$tmp/cam.obj" --up 1,0,0 -q -o "$tmp/one.stream" &&
    cmp -s "$tmp/tiny.stream" "$tmp/one.stream" && ok || bad "a denormal --up is not its direction"
expect 0 '"faces_in": 1' "$bin" gp "$tmp/cam.obj" --eye 1e308,0,0 --json
expect 2 "--eye and --at are too far apart" "$bin" gp "$tmp/cam.obj" --eye 1e308,0,0 --at -1e308,0,0 --json

finish
