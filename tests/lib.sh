# lib.sh — sourced by the command-line test scripts (tests/cli*.sh): a scratch
# directory $tmp removed on exit, ok/bad counters, expect, and the closing
# "N passed, N failed" line (finish).
set -u
bin=${1:-build/albatros}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }

# expect STATUS PATTERN CMD...: exit status and a pattern in stdout+stderr
expect() {
    local want=$1 pat=$2; shift 2
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [[ $rc -ne $want ]]; then bad "$* -> exit $rc, expected $want: $out"; return; fi
    if ! grep -qE -- "$pat" <<<"$out"; then bad "$* -> output lacks /$pat/: $out"; return; fi
    ok
}

# finish: the summary line; a script that ran no test fails
finish() {
    echo "$pass passed, $fail failed"
    [[ $fail -eq 0 && $pass -gt 0 ]]
}

source "$(dirname "${BASH_SOURCE[0]}")/sanitizers.sh"
