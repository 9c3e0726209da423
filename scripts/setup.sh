#!/usr/bin/env bash
# Installs everything LPV Preview needs on a fresh Debian/Ubuntu machine and is quick when
# it already has: Mesa's EGL/OpenGL (llvmpipe) and Xvfb when missing, then a Python 3.11 virtual
# environment in .venv with the pinned packages of requirements.txt, and the repository
# linked into it as the package `lpv_preview`.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for package in libegl1 libegl-mesa0 libgl1 libgl1-mesa-dri; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
command -v Xvfb >/dev/null 2>&1 || missing+=(xvfb)  # a real X server for the GL-context tests
python=$(command -v python3.11 || true)
[ -n "$python" ] || missing+=(python3.11 python3.11-venv)
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
  python=$(command -v python3.11)
fi

if [ ! -x .venv/bin/python ]; then
  "$python" -m venv .venv
fi
stamp=.venv/requirements.installed
if ! cmp -s requirements.txt "$stamp"; then
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install -q -r requirements.txt
  cp requirements.txt "$stamp"
fi
site=$(.venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
ln -sfn "$root" "$site/lpv_preview"
echo "setup: ready ($(.venv/bin/python --version), $(.venv/bin/python -c 'import bpy; print("bpy", bpy.app.version_string)' 2>/dev/null | tail -n 1))"
