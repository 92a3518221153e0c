#!/usr/bin/env bash
# cli-property.sh ALBATROS — the property every writer of albatros keeps,
# checked on the real commands in a scratch directory: whatever stops a run
# (a file-size limit at any point of the file, kill -9 at any moment), the
# output's name holds either the complete new file (byte for byte what an
# unhindered run writes) or the old file untouched, and the exit status says
# which; a run that fails says why and leaves no temporary file.
source "$(dirname "$0")/lib.sh"
bin=$(realpath "$bin")
cd "$tmp" || exit 1

printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5 i 0.2\n v 1 -1 5 i 1\n v 0 1 5 i 0.5\n f 1 2 3\nend\n' > one.scene
"$bin" scene random --faces 300 --seed 9 -o many.scene
"$bin" gp many.scene -q -o many.stream
"$bin" render one.scene -q -o a.exr
"$bin" render one.scene -q --set aa=1 -o b.exr

# prop NAME STATUS CMD...: CMD writes the file @ and exits with STATUS when
# nothing stops it (compare: 1, the frames differ)
prop() {
    local name=$1 want=$2; shift 2
    local args=("${@//@/out}") rc checked=0 broken=""
    rm -f out ref; "$bin" "${args[@]}" > /dev/null 2>&1
    [[ $? -eq $want ]] || { bad "$name: the unhindered run failed"; return; }
    mv out ref
    printf 'the old file, which must survive\n' > old
    # under make memcheck (every run in valgrind) fewer points of the same paths
    local limits=(0 1 2 4 8 16 32 64 128) delays=(0 0.002 0.01 0.03 0.1)
    # (not 0: valgrind itself cannot start without writing its own files)
    [[ -n ${ALBATROS_UNWRAPPED:-} ]] && limits=(4 16) delays=(0.5)
    for limit in "${limits[@]}"; do
        cp old out
        # stderr through a pipe: the limit is the files' (a message in a file over it would be lost)
        msg=$( (ulimit -f "$limit"; exec "$bin" "${args[@]}") 2>&1 > /dev/null); rc=$?
        checked=$((checked + 1))
        if [[ $rc -eq $want ]]; then cmp -s out ref || broken+=" limit=${limit}K:exit-$rc-but-not-the-new-file"
        else
            cmp -s out old || broken+=" limit=${limit}K:exit-$rc-but-old-file-lost"
            [[ -n $msg ]] || broken+=" limit=${limit}K:no-message"
        fi
        compgen -G ".*.tmp" > /dev/null && broken+=" limit=${limit}K:temporary-left"
    done
    for delay in "${delays[@]}"; do
        cp old out
        "$bin" "${args[@]}" > /dev/null 2>&1 &
        local pid=$!
        sleep "$delay"; kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null
        checked=$((checked + 1))
        cmp -s out old || cmp -s out ref || broken+=" kill-after-${delay}s:neither-old-nor-new"
        rm -f .*.tmp   # kill -9 leaves its temporary beside the name, never under it
    done
    [[ -z $broken ]] && ok || bad "$name:$broken"
    echo "# $name: $checked interrupted runs, the old or the whole new file each time"
}

prop "render -o" 0 render many.scene -q --profile a256 -o @
prop "render --png" 0 render many.scene -q --profile a256 --png @
prop "render --view level" 0 render many.scene -q --profile a256 --view level:@
prop "render --dump" 0 render one.scene -q --profile t32 --dump @
prop "render --stream" 0 render many.scene -q --profile t32 --json --stream @
prop "render --vcd" 0 render one.scene -q --profile t32 --fidelity cycle --vcd @
prop "render --events" 0 render one.scene -q --profile t32 --fidelity cycle --events @
prop "vp -o" 0 vp many.stream -q -o @
prop "gp -o" 0 gp many.scene -q -o @
prop "gp --memh" 0 gp many.scene -q --memh @
prop "gp --hex" 0 gp many.scene -q --hex @
prop "scene -o" 0 scene random --faces 500 --seed 3 -o @
prop "compare --diff" 1 compare a.exr b.exr --diff @
prop "reference -o" 0 reference one.scene -q --profile a256 -o @
prop "method -o" 0 method zbuffer many.scene -q --profile a256 -o @

finish
