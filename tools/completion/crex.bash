# bash completion for crex: its commands, each command's options and the values of an option
# with a closed set (--progress auto|bar|plain|none), the stdlib's pipelines, all read from the
# tool's own help, so they cannot drift from the tool; file names elsewhere. Installed to
# share/bash-completion/completions/crex; to try it from a build: source tools/completion/crex.bash
_crex() {
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]} crex=${COMP_WORDS[0]} cmd="" i
    for ((i = 1; i < COMP_CWORD; i++)); do
        case ${COMP_WORDS[i]} in -*) ;; *) cmd=${COMP_WORDS[i]}; break ;; esac
    done
    local commands
    commands=$("$crex" --help 2>/dev/null | sed -n '/^Subcommands:/,/^$/s/^  \([a-z][a-z-]*\) .*/\1/p')
    if [[ -z $cmd || $cmd == help && $COMP_CWORD -eq 2 ]]; then
        if [[ $cur == -* ]]; then
            mapfile -t COMPREPLY < <(compgen -W "--help --version" -- "$cur")
        else
            mapfile -t COMPREPLY < <(compgen -W "$commands" -- "$cur")
        fi
        return
    fi
    local help
    help=$("$crex" help "$cmd" 2>/dev/null) || return
    # The option's own values, where its help line names a set: "--progress TEXT:{auto,bar,plain,none}".
    if [[ $prev == -* && $cur != -* ]]; then
        local set
        set=$(grep -E "^ +(-[a-zA-Z],)?${prev}( |$)" <<< "$help" | grep -o '{[^}]*}' | head -n 1 | tr -d '{}' | tr ',' ' ')
        if [[ -n $set ]]; then
            mapfile -t COMPREPLY < <(compgen -W "$set" -- "$cur")
            return
        fi
    fi
    if [[ $cur == -* ]]; then
        local options
        options=$(grep -E '^ +-' <<< "$help" | awk '{print $1}' | tr ',' '\n')
        mapfile -t COMPREPLY < <(compgen -W "$options" -- "$cur")
        return
    fi
    compopt -o filenames 2> /dev/null
    mapfile -t COMPREPLY < <(compgen -f -- "$cur")
    # A pipeline argument may be a stdlib pipeline's name: the names 'crex run --help' lists.
    if [[ $cmd == @(run|plan|check) && $prev != -* ]]; then
        local names
        names=$("$crex" help run 2>/dev/null | sed -n "/^working folder comes first). The stdlib's/,/^$/{/^  /p}")
        mapfile -t -O "${#COMPREPLY[@]}" COMPREPLY < <(compgen -W "$names" -- "$cur")
    fi
}
complete -F _crex crex
