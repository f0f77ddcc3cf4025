#!/usr/bin/env bash
# Installs what the benchmark harness needs, idempotently: from PyPI into
# bench/.venv (requirements.txt, pinned) Mitsuba 3, embreex (Embree), numpy,
# OpenEXR and maturin (which builds Penumbra's Python module into the venv);
# POV-Ray and an LLVM shared library (for Mitsuba's llvm_ad_rgb variant;
# Dr.Jit needs LLVM 15 or later) from Debian's packages. Needs root (or
# sudo) for apt.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -r "$here/requirements.txt"

have_llvm() { ls /usr/lib/x86_64-linux-gnu/libLLVM-1[5-9].so.1 /usr/lib/x86_64-linux-gnu/libLLVM-2[0-9].so.1 >/dev/null 2>&1; }
if command -v povray >/dev/null 2>&1 && have_llvm; then
    exit 0
fi
sudo=""
if [ "$(id -u)" != 0 ]; then
    sudo="sudo"
fi
$sudo apt-get update -qq
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get install -y -qq povray >/dev/null
if ! have_llvm; then
    for v in 19 16 15; do
        if $sudo apt-get install -y -qq "libllvm$v" >/dev/null 2>&1; then
            break
        fi
    done
fi
