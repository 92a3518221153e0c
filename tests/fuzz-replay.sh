#!/usr/bin/env bash
# fuzz-replay.sh BUILD [WRAPPER ...] — every fuzz harness, built without
# libFuzzer (BUILD/fuzz/replay_TARGET), over its seeds (fuzz/corpus/TARGET)
# and the inputs that once crashed it (fuzz/regress/TARGET).  Under `make
# asan` the sanitizers check them too; `make memcheck` runs each harness
# under the WRAPPER (valgrind).  Ends with "N passed, N failed".
set -u
build=${1:-build}
wrap=("${@:2}")
pass=0 fail=0
for t in scene obj stream png options fw link; do
    bin=$build/fuzz/replay_$t
    dirs=()
    for d in fuzz/corpus/$t fuzz/regress/$t; do [[ -d $d ]] && dirs+=("$d"); done
    if [[ ! -x $bin ]]; then
        echo "FAIL: $bin not built" >&2
        fail=$((fail + 1))
        continue
    fi
    out=$("${wrap[@]}" "$bin" "${dirs[@]}")
    rc=$?
    line=$(tail -n 1 <<<"$out")
    echo "$t: $line"
    if [[ $line =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]]; then
        pass=$((pass + BASH_REMATCH[1]))
        fail=$((fail + BASH_REMATCH[2]))
        [[ $rc -ne 0 && ${BASH_REMATCH[2]} -eq 0 ]] && fail=$((fail + 1))
    else
        echo "FAIL: $bin: no summary line (exit $rc)" >&2
        fail=$((fail + 1))
    fi
done
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
