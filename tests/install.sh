#!/usr/bin/env bash
# install.sh BUILD — make install into a scratch DESTDIR, then use what was
# installed from outside the tree: a C program built with pkg-config
# (examples/replay.c, the docs' 30-line bench, shared and static) run
# through a golden vector, the man page rendered, the installed command
# (stability --jobs names itself), the Python module and the DPI package;
# make uninstall leaves nothing behind.
source "$(dirname "$0")/lib.sh"
build=${1:-build}
src=$(realpath "$(dirname "$0")/..")
dest=$tmp/root prefix=/usr/local
make -s -C "$src" BUILD="$build" install DESTDIR="$dest" PREFIX=$prefix > "$tmp/inst.log" 2>&1 \
    && ok || bad "make install: $(tail -5 "$tmp/inst.log")"
root=$dest$prefix
for f in bin/albatros lib/libalbatros.so.0.1.0 lib/libalbatros.so.0 lib/libalbatros.so lib/libalbatros.a \
         lib/pkgconfig/albatros.pc include/albatros/albatros.h include/albatros/model.h \
         include/albatros/albatros_pkg.sv share/man/man1/albatros.1 share/doc/albatros/cosim.md \
         share/bash-completion/completions/albatros lib/udev/rules.d/70-albatros.rules; do
    [[ -e $root/$f ]] && ok || bad "not installed: $f"
done
# a program outside the tree, from the installed files alone
mkdir -p "$tmp/work" && cp "$src/examples/replay.c" "$tmp/work/" && cd "$tmp/work" || exit 1
export PKG_CONFIG_PATH=$root/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=$dest
flags=$(pkg-config --cflags --libs albatros) && ok || bad "pkg-config albatros"
san=$(sanitizer_flags "$root/lib/libalbatros.so.0")
[[ $flags == *"-I$root/include"* && $flags == *-lalbatros* ]] && ok || bad "pkg-config flags: $flags"
cc -std=c11 -Wall -Wextra -Werror $san replay.c $flags -o replay 2> cc.log && ok || bad "cc with pkg-config: $(cat cc.log)"
vec=$src/test-vectors/builtin
out=$(LD_LIBRARY_PATH=$root/lib ./replay a512 "$vec/expected.stream" "$vec/expected.frames" 2>&1)
[[ $? -eq 0 && $(grep -c '^frame' <<<"$out") -eq 4 && $out != *MISMATCH* ]] && ok || bad "replay (shared): $out"
LD_LIBRARY_PATH=$root/lib ldd ./replay | grep -q "$root/lib/libalbatros.so.0" \
    && ok || bad "replay is not linked to the installed library: $(LD_LIBRARY_PATH=$root/lib ldd ./replay)"
# the static library, its own dependencies shared (docs/cosim.md)
cc -std=c11 -Wall -Wextra -Werror $san replay.c $(pkg-config --cflags albatros) "$root/lib/libalbatros.a" \
    $(pkg-config --libs libpng libusb-1.0 hidapi-hidraw zlib) -lOpenEXRCore-3_1 -lm -pthread \
    -o replay-static 2> cc2.log && ok || bad "static link: $(cat cc2.log)"
! ldd ./replay-static | grep -q libalbatros && ok || bad "replay-static needs the shared library"
out=$(./replay-static a512 "$vec/expected.stream" "$vec/expected.frames" 2>&1)
[[ $? -eq 0 && $out != *MISMATCH* ]] && ok || bad "replay (static): $out"
# a C++ bench (Verilator's, say) includes the headers as they are
printf '#include <albatros/albatros.h>\n#include <cstdio>\nint main() {\n  alb_model *m; alb_diag d;\n  if (alb_model_open(&m, "t32", nullptr, nullptr, &d)) return 1;\n  std::printf("%%s\\n", alb_version());\n  alb_model_destroy(m);\n}\n' > bench.cpp
if command -v g++ >/dev/null; then
    g++ -std=c++17 -Wall -Wextra -Werror -pedantic $san bench.cpp $flags -o bench-cpp 2> cxx.log \
        && [[ $(LD_LIBRARY_PATH=$root/lib ./bench-cpp) == 0.1.0 ]] && ok || bad "C++ bench: $(cat cxx.log)"
fi
# a planted difference is caught: a CRC off by one in the expected frames
awk 'NR == 3 {$2 += 1} {print}' "$vec/expected.frames" > wrong.frames
LD_LIBRARY_PATH=$root/lib ./replay a512 "$vec/expected.stream" wrong.frames > wrong.out 2>&1
[[ $? -ne 0 ]] && grep -q 'frame 2: .*MISMATCH' wrong.out && ok || bad "planted mismatch: $(cat wrong.out)"
# the installed command, its man page and its jobs
"$root/bin/albatros" --version | grep -q '^albatros 0.1.0$' && ok || bad "installed --version"
jobs=$("$root/bin/albatros" stability --jobs | head -1)
[[ $jobs == "$root/bin/albatros stability "* ]] && ok || bad "stability --jobs: $jobs"
(cd / && PATH=$root/bin:$PATH albatros stability --jobs | head -1 | grep -q '^albatros stability ') \
    && ok || bad "stability --jobs from PATH"
MANWIDTH=80 man -l "$root/share/man/man1/albatros.1" > man.txt 2> man.err && grep -q '^SUBCOMMANDS' man.txt \
    && ok || bad "man -l: $(cat man.err)"
[[ ! -s man.err ]] && ok || bad "man warnings: $(cat man.err)"
# every subcommand of --help has its entry
for sub in $("$root/bin/albatros" --help | awk '/^Subcommands:/ {s = 1; next} s && NF && $1 !~ /^-/ {print $1}'); do
    grep -qE "^       $sub( |$)" man.txt && ok || bad "man page lacks the subcommand $sub"
done
# the completion, sourced from where it was installed
comp=$(bash -c "source '$root/share/bash-completion/completions/albatros'
    COMP_WORDS=('$root/bin/albatros' ren); COMP_CWORD=1; _albatros; echo \${COMPREPLY[*]}
    COMP_WORDS=('$root/bin/albatros' vp --events-o); COMP_CWORD=2; _albatros; echo \${COMPREPLY[*]}
    COMP_WORDS=('$root/bin/albatros' render --profile t); COMP_CWORD=3; _albatros; echo \${COMPREPLY[*]}")
[[ $comp == $'render\n--events-only\nt32' ]] && ok || bad "bash completion: $comp"
# the Python module, as installed
pydir=$(dirname "$(find "$root/lib" -name albatros.py | head -1)")
py=$(PYTHONPATH=$pydir ALBATROS_LIB=$root/lib/libalbatros.so.0 $(python_preload "$root/lib/libalbatros.so.0") python3 -c \
    'import albatros; w = albatros.compile_scene(None, "t32"); m = albatros.Model("t32"); m.push(w)
while not m.done: m.run(until=albatros.EV_FRAME)
print(albatros.version(), m.frames)' 2>&1)
[[ $py == "0.1.0 4" ]] && ok || bad "installed Python module: $py"
# the DPI package parses where it was installed
if command -v verilator >/dev/null; then
    printf 'module t; import albatros_pkg::*; initial $display("%%0d", ALB_EV_ALL); endmodule\n' > t.sv
    verilator --lint-only -Wall "$root/include/albatros/albatros_pkg.sv" t.sv 2> vl.log && ok || bad "DPI package: $(cat vl.log)"
fi
cd "$src"
make -s BUILD="$build" uninstall DESTDIR="$dest" PREFIX=$prefix > "$tmp/un.log" 2>&1 && ok || bad "make uninstall"
left=$(find "$dest" -type f -o -type l)
[[ -z $left ]] && ok || bad "left after uninstall: $left"
finish
