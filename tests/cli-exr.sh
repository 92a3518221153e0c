#!/usr/bin/env bash
# cli-exr.sh ALBATROS — frames other tools read right (docs/vp.md, "Frames"):
# OpenImageIO sees linear colour with sRGB primaries, and converting the EXR
# to sRGB gives the PNG preview's pixels; the provenance attributes are there
# and keep files byte-identical for the same input; another tool's EXR (no
# vp.R/G/B) reads back as the same frame store values.
source "$(dirname "$0")/lib.sh"
bin=$(realpath "$bin")

if ! command -v oiiotool > /dev/null; then
    bad "oiiotool is needed (apt-get install openimageio-tools; make deps)"
    finish
    exit
fi
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5 i 0.2\n v 1 -1 5 i 1\n v 0 1 5 i 0.6\n colour 250 120 30\n f 1 2 3\nend\n' > "$tmp/one.scene"
"$bin" render "$tmp/one.scene" -q -o "$tmp/f.exr" --png "$tmp/f.png"
info=$(oiiotool --info -v "$tmp/f.exr" 2>&1)
for want in 'chromaticities: 0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329' 'oiio:ColorSpace: "Linear"' \
            'albatros.colour: "R G B: linear light with sRGB (Rec. 709) primaries' \
            "albatros.software: \"albatros $("$bin" --version | cut -d' ' -f2)\"" 'albatros.profile: "a512"' \
            'albatros.fidelity: "functional"' 'albatros.source: "one.scene"'; do
    grep -qF "$want" <<<"$info" && ok || bad "oiiotool --info -v lacks $want: $info"
done
# what a colour-managed viewer shows: the EXR converted to sRGB is the PNG
# (each channel within one step of 255, the HALF's rounding)
for scene in "$tmp/one.scene" ""; do
    "$bin" render $scene -q -o "$tmp/v.exr" --png "$tmp/v.png"
    exr=$tmp/v.exr png=$tmp/v.png
    [[ -e $tmp/v.0000.exr ]] && exr=$tmp/v.0002.exr png=$tmp/v.0002.png
    oiiotool "$exr" --ch R,G,B --colorconvert linear sRGB -d uint8 -o "$tmp/conv.png" &&
        oiiotool "$tmp/conv.png" "$png" --diff --fail 0.004 > "$tmp/diff.txt" 2>&1 && ok ||
        bad "the EXR in sRGB is not the PNG (${scene:-built-in scene}): $(tail -3 "$tmp/diff.txt")"
done
# the same input, the same bytes: a second run, another folder, other threads
"$bin" render "$tmp/one.scene" -q -o "$tmp/f2.exr" --threads 3
mkdir "$tmp/elsewhere" && cp "$tmp/one.scene" "$tmp/elsewhere/"
(cd "$tmp/elsewhere" && "$bin" render one.scene -q -o f3.exr)
cmp -s "$tmp/f.exr" "$tmp/f2.exr" && cmp -s "$tmp/f.exr" "$tmp/elsewhere/f3.exr" && ok ||
    bad "the same input gave different EXR bytes"
"$bin" render "$tmp/one.scene" -q -o "$tmp/t.exr" --fidelity timed
grep -q 'albatros.fidelity: "timed"' <<<"$(oiiotool --info -v "$tmp/t.exr" 2>&1)" && ok || bad "timed fidelity not recorded"
expect 0 "albatros.source" exrheader "$tmp/f.exr"
# another tool's EXR: linear R G B without vp.R/G/B reads as the same store values
oiiotool "$tmp/f.png" --colorconvert sRGB linear -d half -o "$tmp/foreign.exr"
expect 1 " 0 with a different colour" "$bin" compare "$tmp/foreign.exr" "$tmp/f.exr"
finish
