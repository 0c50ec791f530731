#!/bin/sh
# crex.1 from the tool's own help: help2man for the overview, then a section a command with
# what `crex help COMMAND` says, so the man page says what --help says and cannot drift.
# Usage: make_man_page.sh CREX OUT   (the build runs it when help2man is installed)
set -eu
crex=$1 out=$2
extra=$(mktemp)
trap 'rm -f "$extra" "$out.tmp"' EXIT
{
    echo "[COMMANDS]"
    for c in $("$crex" --help | sed -n '/^Subcommands:/,/^$/s/^  \([a-z][a-z-]*\) .*/\1/p'); do
        [ "$c" = help ] && continue
        echo ".SS crex $c"
        echo ".nf"
        # roff: a backslash is written twice, a line starting with . or ' is escaped
        "$crex" help "$c" | sed -e 's/\\/\\\\/g' -e "s/^\\([.']\\)/\\\\\\&\\1/"
        echo ".fi"
    done
    echo "[EXIT STATUS]"
    echo "0 success, or warnings only; 1 the input has errors (diagnostics on stderr); 2 a bad command line;"
    echo "3 an I/O or run-time failure; 130 interrupted (crex run writes the image so far to NAME.partial.EXT first)."
    echo "[SEE ALSO]"
    echo "The guides installed in share/doc/crex (docs/ of the source): crex-language.md, pipeline-language.md, runtime.md and the rest."
} > "$extra"
help2man --no-info --no-discard-stderr --name "compile and run selective-rendering pipelines" --section 1 \
    --include "$extra" --output "$out.tmp" "$crex"
mv "$out.tmp" "$out"
