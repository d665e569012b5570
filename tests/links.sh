#!/bin/sh
# Every relative link and image in the README and the manual resolves: the
# file (or folder) exists, and a "#anchor" into a Markdown file names one of
# its headings (GitHub's slug: lower case, punctuation dropped, spaces to -).
# Links inside code (`...` and fenced blocks) are not links. Usage: links.sh SOURCE_DIR
set -u
root=$1
cd "$root" || exit 2
fail=0
slugs() { # the anchors of a Markdown file's headings
    awk '/^```/ {code = !code; next} !code && /^#+ / {sub(/^#+ +/, ""); print}' "$1" |
        sed -e 's/`//g' -e 's/\[\([^]]*\)\]([^)]*)/\1/g' | tr 'A-Z' 'a-z' |
        sed -e 's/[^a-z0-9 _-]//g' -e 's/ /-/g'
}
for file in README.md CHANGELOG.md DESIGN.md docs/*.md bench/results/notes/*.md; do
    dir=$(dirname "$file")
    # the links outside code: drop fenced blocks and inline code first
    awk '/^```/ {code = !code; next} !code' "$file" | sed 's/`[^`]*`//g' |
        grep -o '\]([^)[:space:]]*)' | sed -e 's/^](//' -e 's/)$//' > "${TMPDIR:-/tmp}/links.$$"
    while IFS= read -r link; do
        case $link in http://* | https://* | mailto:*) continue ;; esac
        target=${link%%#*}
        anchor=
        case $link in *'#'*) anchor=${link#*#} ;; esac
        if [ -z "$target" ]; then path=$file; else path=$dir/$target; fi
        if [ ! -e "$path" ]; then
            echo "$file: broken link '$link' ($path does not exist)"
            fail=1
        elif [ -n "$anchor" ] && [ "${path%.md}" != "$path" ]; then
            if ! slugs "$path" | grep -qx -- "$anchor"; then
                echo "$file: broken anchor '$link' (no such heading in $path)"
                fail=1
            fi
        fi
    done < "${TMPDIR:-/tmp}/links.$$"
    rm -f "${TMPDIR:-/tmp}/links.$$"
done
[ $fail -eq 0 ] && echo "links: every relative link and image resolves"
exit $fail
