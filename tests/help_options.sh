#!/bin/sh
# `softbond --help` and each command's --help name every option the command
# accepts. The options are read from the commands' own lists in the source
# (the `accepted[]` array each command hands sb_cli_parse; tetra's and keys'
# own comparisons), so a new option without help text fails here.
# Usage: help_options.sh SOURCE_DIR PROGRAM
set -u
src=$1
program=$2
fail=0
top=$("$program" --help) || { echo "softbond --help failed"; exit 1; }
options_of() { # the options a command's source accepts
    case $1 in
    run) file=run.c ;; view) file=view_cli.c ;; film) file=film.c ;; eval) file=eval.c ;;
    info) file=info.c ;; tetra) file=tetra.c ;; keys) file=keys.c ;; sweep) file=sweep.c ;; fit) file=fit.c ;;
    esac
    case $1 in
    tetra | keys) grep -oE '(strcmp\([^,]*|option_value\([^"]*), "--[a-z-]*"\)' "$src/cli/$file" | grep -o '"--[a-z-]*"' ;;
    *) sed -n '/accepted\[\] = {/,/};/p' "$src/cli/$file" | grep -o '"--[a-z-]*"' ;;
    esac | tr -d '"' | grep -vx -- '--help' | sort -u
    case $1 in run | view | film | eval | sweep | fit) echo "--set" ;; esac
}
for command in run view film eval info tetra keys sweep fit; do
    own=$("$program" "$command" --help) || { echo "softbond $command --help failed"; fail=1; continue; }
    case $top in *"softbond $command "* | *"softbond $command") ;; *) echo "softbond --help does not show '$command'"; fail=1 ;; esac
    count=0
    for option in $(options_of "$command"); do
        count=$((count + 1))
        case $own in *"$option"*) ;; *) echo "softbond $command --help does not name $option"; fail=1 ;; esac
        # in the overview, on the command's own lines (from its name to the next command)
        lines=$(printf '%s\n' "$top" | awk -v c="softbond $command " '
            index($0, "softbond ") && !index($0, c) {on = 0} index($0, c) {on = 1} on')
        case $lines in *"$option"*) ;; *) echo "softbond --help does not name $command's $option"; fail=1 ;; esac
    done
    echo "$command: $count options checked"
done
[ $fail -eq 0 ] && echo "help: every option of every command is in its --help and in softbond --help"
exit $fail
