#!/bin/sh
# profile-params.sh — a profile of the family (docs/profiles.md) as the RTL's
# parameters (rtl/README.md), so the same RTL builds for any member and any
# --set overrides:
#
#   rtl/profile-params.sh [--format verilator|icarus|svh|shell] [--top MODULE]
#                         [--albatros PATH] [--profile] PROFILE [--set key=value ...]
#                         [--rtl NAME=VALUE ...]
#
# verilator: -GNAME=VALUE options; icarus: -PMODULE.NAME=VALUE options; svh:
# `define ALB_NAME VALUE lines; shell: NAME=VALUE lines.  --set goes to
# `albatros profiles`, which checks it; --rtl sets a parameter the profile does
# not have (TEX_WORDS, SCAN_PIXELS, MAX_EDGES).
set -eu
format=verilator
top=alb_vp
albatros=${ALBATROS:-build/albatros}
profile=
sets=
rtl=
die() { echo "profile-params.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case $1 in
        --format) [ $# -ge 2 ] || die "--format needs a value"; format=$2; shift 2 ;;
        --top) [ $# -ge 2 ] || die "--top needs a value"; top=$2; shift 2 ;;
        --albatros) [ $# -ge 2 ] || die "--albatros needs a value"; albatros=$2; shift 2 ;;
        --set) [ $# -ge 2 ] || die "--set needs key=value"; sets="$sets --set $2"; shift 2 ;;
        --profile) [ $# -ge 2 ] || die "--profile needs a name"
                   [ -z "$profile" ] || die "one profile, got $profile and $2"; profile=$2; shift 2 ;;
        --rtl) [ $# -ge 2 ] || die "--rtl needs NAME=VALUE"
               case $2 in *=*) ;; *) die "--rtl $2: expected NAME=VALUE" ;; esac
               rtl="$rtl $2"; shift 2 ;;
        -*) die "unknown option $1" ;;
        *) [ -z "$profile" ] || die "one profile, got $profile and $1"; profile=$1; shift ;;
    esac
done
[ -n "$profile" ] || die "usage: profile-params.sh [--format F] PROFILE [--set k=v ...]"
case $format in verilator|icarus|svh|shell) ;; *) die "unknown format $format" ;; esac
[ -x "$albatros" ] || die "$albatros: not found (build it with make, or pass --albatros)"

# `albatros profiles NAME --set ...` prints the one profile; an albatros
# without it lists them all, and the overrides are applied here.
# shellcheck disable=SC2086
if ! kv=$("$albatros" profiles "$profile" $sets 2>/dev/null); then
    kv=$("$albatros" profiles | awk -v p="$profile" '
        /^profile=/ { on = ($0 == "profile=" p) } on && NF { print }')
    [ -n "$kv" ] || die "no profile '$profile' (albatros profiles lists them)"
    for s in $sets; do
        case $s in --set) continue ;; esac
        key=${s%%=*}
        echo "$kv" | grep -q "^$key=" || die "--set $s: the profile has no field '$key'"
        kv=$(echo "$kv" | sed "s/^$key=.*/$s/")
    done
fi

emit() {
    case $format in
        verilator) printf -- '-G%s=%s\n' "$1" "$2" ;;
        icarus) printf -- '-P%s.%s=%s\n' "$top" "$1" "$2" ;;
        svh) printf '`define ALB_%s %s\n' "$1" "$2" ;;
        shell) printf '%s=%s\n' "$1" "$2" ;;
    esac
}
# the fields the VP uses, in the order of docs/profiles.md
for key in width height aa edge_frac_bits coef_bits depth_bits colour_bits recip_bits \
           shade_frac_bits fifo_depth face_slots edge_units fill_rate fill_queue \
           frame_queue divider_latency shade_latency frame_faces; do
    value=$(echo "$kv" | sed -n "s/^$key=//p")
    [ -n "$value" ] || die "profile $profile has no field $key"
    emit "$(echo "$key" | tr a-z A-Z)" "$value"
done
for nv in $rtl; do
    emit "${nv%%=*}" "${nv#*=}"
done
