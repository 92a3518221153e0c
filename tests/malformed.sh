#!/usr/bin/env bash
# malformed.sh ALBATROS [--pending] — the hand-made malformed inputs of
# tests/data/malformed: each case of cases.txt runs the CLI on one input and
# checks the exit status and the exact error line (message and file:line:col
# or byte offset).  --pending runs pending.txt instead: the cases whose
# current handling is known to be wrong.  Ends with "N passed, N failed".
set -u
bin=${1:-build/albatros}
table=cases.txt
[[ ${2:-} == --pending ]] && table=pending.txt
cd "$(dirname "$0")/.." || exit 2
[[ $bin == /* ]] || bin=$PWD/${bin#./}
dir=tests/data/malformed
pass=0 fail=0
trim() { local s=$1; s=${s#"${s%%[! ]*}"}; printf '%s' "${s%"${s##*[! ]}"}"; }
# the file's path as a regex: every character that means something escaped
regex_quote() { sed 's/[][\\.*^$+?(){}|]/\\&/g' <<<"$1"; }

lineno=0
while IFS= read -r line || [[ -n $line ]]; do
    lineno=$((lineno + 1))
    [[ -z ${line// /} || $line == \#* ]] && continue
    # FILE | ARGS | STATUS | REGEX (the regex may itself contain " | ")
    file=$(trim "${line%% | *}"); rest=${line#* | }
    args=$(trim "${rest%% | *}"); rest=${rest#* | }
    want=$(trim "${rest%% | *}"); regex=$(trim "${rest#* | }")
    if [[ -z $file || -z $args || ! $want =~ ^[0-9]+$ || -z $regex ]]; then
        echo "FAIL: $table:$lineno: not FILE | ARGS | STATUS | REGEX" >&2
        fail=$((fail + 1))
        continue
    fi
    path=
    if [[ $file != - ]]; then
        path=$dir/$file
        if [[ ! -e $path ]]; then
            echo "FAIL: $table:$lineno: no file $path" >&2
            fail=$((fail + 1))
            continue
        fi
    fi
    args=${args//@/$path}
    regex=${regex//@/$(regex_quote "$path")}
    # shellcheck disable=SC2086  # ARGS are split at spaces on purpose
    err=$(timeout 60 "$bin" $args 2>&1 >/dev/null)
    rc=$?
    if [[ $rc -ne $want ]]; then
        echo "FAIL: $table:$lineno: albatros $args -> exit $rc, expected $want: $err" >&2
        fail=$((fail + 1))
    elif ! grep -qxE -- "$regex" <<<"$err"; then
        echo "FAIL: $table:$lineno: albatros $args -> no line matches /$regex/: $err" >&2
        fail=$((fail + 1))
    else
        pass=$((pass + 1))
    fi
done < "$dir/$table"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
