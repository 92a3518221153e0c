#!/usr/bin/env bash
# doc-numbers.sh ALBATROS BUILD — numbers the documents state, checked
# against what the code does: the edge units' register widths of docs/vp.md
# (recomputed from the profiles), the limits of docs/limits.md (each tried
# on the command line, the GP's edges per face counted on a 32-gon), the
# profile table of docs/profiles.md (against `albatros profiles`), the
# section numbers docs/word-format.md cites, and docs/number-formats.md's "the
# VP has no floating point" (no floating-point instruction in BUILD/vp/*.o).
# Then the same checks on a copy of the documents with numbers planted wrong
# (the old ones), each of which must be caught.
source "$(dirname "$0")/lib.sh"
build=${2:-build}

# one field of one profile, from `albatros profiles` (run once)
"$bin" profiles > "$tmp/profiles" || bad "albatros profiles failed"
field() { awk -v p="profile=$1" -v k="$2" '$0 == p {on = 1; next} /^profile=/ {on = 0}
                                                          on && index($0, k "=") == 1 {sub(/^[^=]*=/, ""); print}' "$tmp/profiles"; }
log2() { local v=$1 n=0; while (( (1 << n) < v )); do n=$((n + 1)); done; echo $n; }

# check_docs DIR: one line per mismatch on stdout
check_docs() {
    local d=$1
    # docs/vp.md: F + max(lw, lh) + 7 bits for a1024 and t32
    local re="\(([0-9]+) bits for a1024's F = ([0-9]+) and lw = ([0-9]+), ([0-9]+) for t32's F = ([0-9]+) and lw = ([0-9]+)"
    local text
    text=$(tr '\n' ' ' < "$d/vp.md" | tr -s ' ')
    if [[ $text =~ $re ]]; then
        local i=1 p
        for p in a1024 t32; do
            local f w h l
            f=$(field $p edge_frac_bits) w=$(field $p width) h=$(field $p height)
            l=$(log2 $(( w > h ? w : h )))
            [[ ${BASH_REMATCH[i]} == $((f + l + 7)) && ${BASH_REMATCH[i + 1]} == "$f" &&
               ${BASH_REMATCH[i + 2]} == "$l" ]] ||
                echo "vp.md: $p's registers are $((f + l + 7)) bits (F = $f, lw = $l), the text says ${BASH_REMATCH[i]} (F = ${BASH_REMATCH[i + 1]}, lw = ${BASH_REMATCH[i + 2]})"
            i=$((i + 3))
        done
    else
        echo "vp.md: the sentence on the edge units' register widths is missing"
    fi
    # docs/limits.md: bounding edges per face by method, counted on a 32-gon
    # (regular: every vertex gets a bisector edge) and on the faces that
    # would get three under bound=albatros
    local row
    row=$(grep '^| edges per face |' "$d/limits.md")
    re='at most 32 own edges plus ([0-9]+) bounding edges \(`bound=albatros`[^)]*\), ([0-9]+) \(`box`\) or ([0-9]+) \(`bisector`'
    if [[ $row =~ $re ]]; then
        local alb=${BASH_REMATCH[1]} box=${BASH_REMATCH[2]} bis=${BASH_REMATCH[3]} m got
        local scene="$tmp/gon.scene"
        { echo "albatros-scene 1"; echo "observer fov 90"; echo "object gon"
          for k in $(seq 0 31); do
              awk -v k=$k 'BEGIN { a = 2 * 3.14159265358979 * k / 32; printf " v %.17g %.17g 5\n", 3 * cos(a), 3 * sin(a) }'
          done
          echo -n " f"; for k in $(seq 1 32); do echo -n " $k"; done; echo; echo end; } > "$scene"
        for m in box:$box bisector:$bis; do
            got=$("$bin" gp "$scene" --set bound=${m%%:*} --json -o "$tmp/g.stream" 2>/dev/null |
                  grep -o '"edges_out": [0-9]*' | grep -o '[0-9]*$')
            [[ $got == $((32 + ${m##*:})) ]] ||
                echo "limits.md: bound=${m%%:*} on a 32-gon gives $got edges, the table says 32 + ${m##*:}"
        done
        got=$("$bin" gp ../test-vectors/bound-at-most-two/scene.scene --profile a256 --json -o "$tmp/g.stream" 2>/dev/null |
              grep -o '"bound_added": [0-9]*' | grep -o '[0-9]*$')
        [[ -n $got && $got -le $((2 * alb)) && $got -gt $((2 * (alb - 1))) ]] ||
            echo "limits.md: bound=albatros gives $got bounding edges on the two faces of bound-at-most-two, the table says at most $alb each"
    else
        echo "limits.md: the edges-per-face row does not give the bounding edges per method"
    fi
    # docs/limits.md: the limits of the table, each just past its end
    local lim
    while IFS='|' read -r name value cmd pat; do
        row=$(grep "^| $name |" "$d/limits.md")
        [[ $row == *"$value"* ]] || { echo "limits.md: the $name row does not say $value"; continue; }
        out=$(eval "\"\$bin\" $cmd" 2>&1)
        [[ $out =~ $pat ]] || echo "limits.md: $name: '$cmd' answers '$out', not /$pat/ (the table says $value)"
    done <<'EOF'
vertices per face| 3..32 |gp "$tmp/v33.scene" -o "$tmp/x.stream"|more than 32 vertices
faces per frame| 16,777,215 |gp --set frame_faces=16777216 -o "$tmp/x.stream"|16777215
screen| 2..8192 per side|gp --size 16384x16384 -o "$tmp/x.stream"|at most 8192
GP → VP FIFO| 1..1,048,576 words |gp --set fifo_depth=1048577 -o "$tmp/x.stream"|must be in 1\.\.1048576 words
faces loaded ahead| 1..64 |gp --set face_slots=65 -o "$tmp/x.stream"|must be in 1\.\.64
threads| 1..64 |render --threads 65 --json|expected 0 \(one per core\) to 64
near| 1.17549e-38 .. 3.40282e+38 |gp --near 1e39 -o "$tmp/x.stream"|1\.17549e-38 \.\. 3\.40282e\+38
EOF
    # docs/profiles.md: the table of each profile's fields
    local header profiles=() k
    header=$(grep '^| key | a512 ' "$d/profiles.md" | head -1)
    IFS='|' read -ra profiles <<<"$header"
    while IFS= read -r row; do
        IFS='|' read -ra cell <<<"$row"
        local key=${cell[1]//[ \`]/}
        for k in 2 3 4 5 6; do
            local p=${profiles[k]// /} want=${cell[k]// /}
            if [[ $key == width×height ]]; then
                got="$(field "$p" width)×$(field "$p" height)"
            else
                got=$(field "$p" "$key")
            fi
            [[ $got == "$want" ]] || echo "profiles.md: $p's $key is $got, the table says $want"
        done
    done < <(grep -E '^\| `[a-z_]+`( × `height`)? \|' "$d/profiles.md")
    # docs/vp.md §9: the threads' tiles, batches and chunks, as vp/ defines them
    local tpt mt vb cpt nc wa
    tpt=$(def VP_TILES_PER_THREAD) mt=$(def VP_MAX_TILES) vb=$(def VP_BATCH)
    cpt=$(def VP_CHUNKS_PER_THREAD) nc=$(def VP_CHUNKS) wa=$(def VP_WALK_ALONE)
    [[ -n $tpt && -n $mt && -n $vb && -n $cpt && -n $nc && -n $wa ]] ||
        echo "vp/: a constant of the threads is not found"
    local nine
    nine=$(sed -n '/^## 9\. /,/^## 10\. /p' "$d/vp.md" | tr '\n' ' ' | tr -s ' ')
    for want in "with at least $tpt per thread, at most $mt," "into batches of $vb." \
                "$cpt a thread (at most $nc, and one for a batch of fewer than $wa faces,"; do
        [[ $nine == *"$want"* ]] || echo "vp.md §9 does not say \"$want\""
    done
    # docs/word-format.md: every § it cites is one of its sections
    local s
    for s in $(grep -o '(§[0-9]*' "$d/word-format.md" | tr -d '(§' | sort -u); do
        grep -q "^## $s\. " "$d/word-format.md" || echo "word-format.md cites §$s, which it does not have"
    done
}

# a constant #defined in vp/ (its first definition)
src=$(cd "$(dirname "$0")/.." && pwd)
def() { grep -h "^#define $1 " "$src"/vp/*.c "$src"/vp/*.h | head -1 | awk '{print $3}'; }

# a face of 33 vertices for the vertices-per-face limit
{ echo "albatros-scene 1"; echo "object t"
  for k in $(seq 0 32); do awk -v k=$k 'BEGIN { a = 6.283185307179586 * k / 33; printf " v %.17g %.17g 5\n", cos(a), sin(a) }'; done
  echo -n " f"; for k in $(seq 1 33); do echo -n " $k"; done; echo; echo end; } > "$tmp/v33.scene"

cd "$(dirname "$0")/../docs" || exit 1
[[ $bin == /* ]] || bin=$OLDPWD/$bin
[[ $build == /* ]] || build=$OLDPWD/$build
out=$(check_docs .)
[[ -z $out ]] && ok || bad "the documents disagree with the code:"$'\n'"$out"

# docs/number-formats.md §0: no floating point in the VP's objects
objs=("$build"/vp/*.o)
if [[ -e ${objs[0]} ]]; then
    fp=$(objdump -d --no-show-raw-insn "${objs[@]}" |
         grep -E $'\t(cvt[a-z0-9]*|(add|sub|mul|div|sqrt|min|max)[sp][sd]|u?comis[sd]|f(ld|st|add|mul|div))\\b' | head -3)
    [[ -z $fp ]] && ok || bad "the VP's objects hold floating-point instructions: $fp"
    # and the check sees one where there is one: the frame's float conversion
    # it was moved out of vp/ for
    fp=$(objdump -d --no-show-raw-insn "$build/emu/frame_out.o" | grep -cE $'\t(cvt[a-z0-9]*|divsd)\\b')
    [[ $fp -gt 0 ]] && ok || bad "no floating-point instruction found in emu/frame_out.o: the check sees nothing"
else
    bad "no objects in $build/vp to check"
fi

# planted: the numbers the documents used to state, one at a time
plant() {   # FILE SED-EXPRESSION EXPECTED-COMPLAINT
    rm -rf "$tmp/docs" && cp -r . "$tmp/docs"
    sed -i "$2" "$tmp/docs/$1"
    cmp -s "$1" "$tmp/docs/$1" && { bad "planting '$2' in $1 changed nothing"; return; }
    local got
    got=$(check_docs "$tmp/docs")
    [[ $got == *"$3"* ]] && ok || bad "planted '$2' in $1 not caught: ${got:-(no complaint)}"
}
plant vp.md 's/22 for t32/27 for t32/' "vp.md: t32's registers are 22 bits"
plant limits.md 's/or 32 (`bisector`/or 4 (`bisector`/' "bound=bisector on a 32-gon gives 64 edges, the table says 32 + 4"
plant limits.md 's/| 1\.\.64 (default: one per core/| 1..128 (default: one per core/' "the threads row does not say  1..64 "
plant profiles.md '/^| `edge_frac_bits`/s/| 13 |/| 12 |/' "profiles.md: a256's edge_frac_bits is 13, the table says 12"
plant vp.md 's/with at least 8 per thread/with at least 16 per thread/' "vp.md §9 does not say \"with at least 8 per thread, at most 1024,\""
plant word-format.md 's/(§4, "Edges"/(§5/' "word-format.md cites §5, which it does not have"
finish
