#!/usr/bin/env bash
# Make the venv VENV (default .venv) with PYTHON (default python3) and install SPEC into it
# (editable, e.g. '.' or '.[test]'), with a pip for the venv's users. `make` runs this.
#
# uv installs, from a copy kept per user (uv/ in the project's cache root, the kernels' too:
# rvcore._numba.cache_root, ~/.cache/rv-bearing-sweep by default): the system's pip puts it
# there on first use and again when that copy is 30 days old. uv resolves against the package index at most once a day on a
# machine: within a day of its last online install, it installs from its own cache
# (--offline), which then holds what that install resolved; when that fails (a package
# not yet cached), it goes online. Where uv cannot be had or cannot install (no wheel for
# the platform, an index only pip.conf names), pip does it: the newest pip, put there by
# the system's pip, or venv's bundled one (ensurepip) upgraded.
set -euo pipefail
SPEC=${1:?usage: tools/install_venv.sh SPEC}
PYTHON=${PYTHON:-python3}
VENV=${VENV:-.venv}
BIN=$VENV/bin
CACHE=$("$PYTHON" "$(dirname "$0")/compile_bytecode.py" --cache-root 2>/dev/null) || CACHE=""
UVHOME=$CACHE/uv
UV=$UVHOME/bin/uv

"$PYTHON" -m venv --without-pip "$VENV"

# uv kept per user: installed into a folder of its own, then renamed into place, so that
# two makes at once each see a whole copy (the second's rename fails and it uses the first's)
have_uv() {
    [ -n "$CACHE" ] || return 1
    if [ -x "$UV" ] && [ -n "$(find "$UVHOME/.installed" -mtime -30 2>/dev/null)" ]; then
        return 0
    fi
    mkdir -p "$(dirname "$UVHOME")" 2>/dev/null || return 1
    local tmp
    tmp=$(mktemp -d "$UVHOME.XXXXXX" 2>/dev/null) || return 1
    if "$PYTHON" -m pip install --quiet --target "$tmp" uv >/dev/null 2>&1 && [ -x "$tmp/bin/uv" ]; then
        touch "$tmp/.installed"
        [ -d "$UVHOME" ] && [ -z "$(find "$UVHOME/.installed" -mtime -30 2>/dev/null)" ] && rm -rf "$UVHOME"
        # a rename that fails where another make's copy is already in place
        "$PYTHON" -c 'import os, sys; os.rename(sys.argv[1], sys.argv[2])' "$tmp" "$UVHOME" 2>/dev/null ||
            rm -rf "$tmp"
    else
        rm -rf "$tmp"
    fi
    [ -x "$UV" ]
}

uv_install() {
    local args=(pip install --quiet --python "$BIN/python" -e "$SPEC" pip)
    if [ -n "$(find "$UVHOME/.online" -mmin -1440 2>/dev/null)" ] && "$UV" "${args[@]}" --offline 2>/dev/null; then
        return 0
    fi
    "$UV" "${args[@]}" && touch "$UVHOME/.online"
}

if ! { have_uv && uv_install; }; then
    echo "uv unavailable: installing with pip"
    "$PYTHON" -m pip --python "$BIN/python" install --quiet --upgrade pip 2>/dev/null ||
        { "$BIN/python" -m ensurepip && "$BIN/python" -m pip install --quiet --upgrade pip; }
    "$BIN/python" -m pip install --quiet --no-compile -e "$SPEC"
fi
