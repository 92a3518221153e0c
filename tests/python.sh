#!/usr/bin/env bash
# python.sh BUILD — the Python module (python/albatros.py, ctypes) over the
# shared library in BUILD/lib, with Debian's python3.
build=${1:-build}
so=$(ls "$build"/lib/libalbatros.so.0 2>/dev/null)
if ! command -v python3 >/dev/null || [[ -z $so ]]; then
    echo "FAIL: needs python3 and $build/lib/libalbatros.so.0" >&2
    echo "0 passed, 1 failed"
    exit 1
fi
source "$(dirname "$0")/sanitizers.sh"
ALBATROS_LIB=$(realpath "$so") exec $(python_preload "$so") python3 "$(dirname "$0")/python/test_model.py"
