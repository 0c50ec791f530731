#!/bin/sh
# `cmake --install` into a fresh prefix, then the installed tool and (when built) the Python
# package used from there: the stdlib, the image plugin and the module must be the installed
# ones, not the build tree's (which would still be found, as a last resort, while it exists).
# Usage: installed_tree_test.sh BUILD_DIR PYTHON PYTHON_INSTALL_DIR   (PYTHON "": no module)
set -eu
build=$1 python=$2 python_dir=$3
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
cd "$prefix"

# The tool renders a pipeline of the installed stdlib; the plugin it loads is the installed one
# (an .hdr takes it: EXR and PNG are written without it).
LD_DEBUG=files "$prefix/bin/crex" run share/crex/stdlib/pipelines/sel_rp.pipe --size 16x12 -q -o out.png -o out.hdr 2> ld.log
test -s out.png && test -s out.hdr
grep -q "file=$prefix/lib[^ ]*/crex/libcrex_oiio.so" ld.log || { echo "the installed image plugin was not the one loaded"; exit 1; }

# A stdlib pipeline by its name alone, from any folder.
mkdir elsewhere && (cd elsewhere && "$prefix/bin/crex" run sel_quiet --size 16x12 -q -o by_name.png) && test -s elsewhere/by_name.png

# `extends` reads the installed stdlib: without its sel_rp, a pipeline extending it is refused,
# and so is sel_rp by name.
printf 'pipeline mine extends sel_rp {\n  preselective { spp 2 }\n}\n' > mine.pipe
"$prefix/bin/crex" check -q mine.pipe
rm share/crex/stdlib/pipelines/sel_rp.pipe
if "$prefix/bin/crex" check -q mine.pipe 2> check.log; then echo "extends read a stdlib outside the prefix"; exit 1; fi
grep -q "E210" check.log
if "$prefix/bin/crex" run sel_rp --size 8x8 -q -o x.png 2> name.log; then echo "crex run sel_rp read a stdlib outside the prefix"; exit 1; fi
grep -q "nor is it a stdlib pipeline" name.log

# The man page (a section a command, from their --help) and bash completion (which reads the
# installed tool's help), where man and bash-completion look.
if command -v help2man > /dev/null; then
    for c in check scene-info run plan compare reference; do
        grep -q "^\.SS crex $c" share/man/man1/crex.1 || { echo "the man page has no section for crex $c"; exit 1; }
    done
    grep -q -- '--progress' share/man/man1/crex.1 || { echo "the man page lacks crex run's options"; exit 1; }
fi
complete_words() {  # what bash completes for the words given, the last one being completed
    bash -c '. share/bash-completion/completions/crex; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _crex; echo "${COMPREPLY[*]}"' \
        complete "$prefix/bin/crex" "$@"
}
test -s share/doc/crex/crex-language.md || { echo "the guides are not installed"; exit 1; }
[ "$(complete_words ru)" = run ] || { echo "completion of 'crex ru' gave '$(complete_words ru)'"; exit 1; }
[ "$(complete_words run --pro)" = "--profile --progress" ] || { echo "completion of 'crex run --pro': '$(complete_words run --pro)'"; exit 1; }
[ "$(complete_words run --progress p)" = plain ] || { echo "completion of 'crex run --progress p': '$(complete_words run --progress p)'"; exit 1; }
[ "$(complete_words run sel_q)" = sel_quiet ] || { echo "completion of 'crex run sel_q': '$(complete_words run sel_q)'"; exit 1; }

[ -n "$python" ] || exit 0
# The package imports from the prefix, renders, and writes through the installed plugin.
PYTHONPATH="$prefix/$python_dir" LD_DEBUG=files "$python" -c "
import crex, os, sys
assert crex.__file__.startswith('$prefix'), crex.__file__
r = crex.run('(TTMRSGD)*', size=(16, 12), output='py.hdr')
assert r.image.shape == (12, 16, 3) and os.path.getsize('py.hdr') > 0
" 2> py.log || { cat py.log | grep -v '^ *[0-9]*:' >&2; exit 1; }
grep -q "file=$prefix/lib[^ ]*/crex/libcrex_oiio.so" py.log || { echo "the module loaded another image plugin"; exit 1; }
echo "installed tree ok: $prefix"
