# bash completion for albatros(1): subcommands, each one's options (read
# from its own --help, so they never go stale), profile names, and files.
_albatros()
{
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}
    local cmd=${COMP_WORDS[0]}
    if (( COMP_CWORD == 1 )); then
        COMPREPLY=($(compgen -W "$("$cmd" --help 2>/dev/null |
            awk '/^Subcommands:/ {s = 1; next} s && NF {print $1}') --help --version" -- "$cur"))
        return
    fi
    local sub=${COMP_WORDS[1]}
    case $prev in
        --profile)
            COMPREPLY=($(compgen -W "$("$cmd" profiles 2>/dev/null | sed -n 's/^profile=//p')" -- "$cur"))
            return ;;
        --fidelity)
            COMPREPLY=($(compgen -W "functional timed cycle" -- "$cur"))
            return ;;
        --vcd-units)
            COMPREPLY=($(compgen -W "all gp fifo parser engine fill pipe" -- "$cur"))
            return ;;
        --events-only)
            COMPREPLY=($(compgen -W "all push pop load start cell end fill write frame" -- "$cur"))
            return ;;
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$("$cmd" "$sub" --help 2>/dev/null |
            grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)" -- "$cur"))
        return
    fi
    case $sub in
        scene)
            if (( COMP_CWORD == 2 )); then
                COMPREPLY=($(compgen -W "random slivers $("$cmd" stability --jobs 2>/dev/null |
                    grep -oE -- '--family [a-z0-9-]+' | cut -d' ' -f2)" -- "$cur"))
                return
            fi ;;
        vectors) (( COMP_CWORD == 2 )) && { COMPREPLY=($(compgen -W "check bless" -- "$cur")); return; } ;;
        board) (( COMP_CWORD == 2 )) && { COMPREPLY=($(compgen -W "list info reset" -- "$cur")); return; } ;;
    esac
    COMPREPLY=($(compgen -f -- "$cur"))
}
complete -o filenames -F _albatros albatros
