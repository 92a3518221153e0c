# sanitizers.sh — sourced by test scripts that build or load against the
# library, so they also run under make asan.
# sanitizer_flags LIB: the -fsanitize flags a program linking LIB needs (the
# make asan build's library pulls in the sanitizer runtimes)
sanitizer_flags() {
    local deps
    deps=$(ldd "$1" 2>/dev/null)
    [[ $deps == *libasan* ]] && printf -- '-fsanitize=address,undefined,float-cast-overflow'
}
# python_preload LIB: an env(1) prefix that lets python3 load an ASan-built
# LIB (the runtime must come first; python's own allocations are no leaks)
python_preload() {
    [[ -n $(sanitizer_flags "$1") ]] || return 0
    printf 'env LD_PRELOAD=%s:%s ASAN_OPTIONS=detect_leaks=0' "$(gcc -print-file-name=libasan.so)" \
        "$(gcc -print-file-name=libubsan.so)"
}
