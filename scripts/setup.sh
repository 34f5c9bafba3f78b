#!/usr/bin/env bash
# Create or refresh .venv: a CPU build of torch first, then dynnav with its test, docs, bench
# and tensorboard extras; then make sure SAPIEN can render (installing Mesa's lavapipe from bookworm-backports
# when run as root).
set -euo pipefail
cd "$(dirname "$0")/.."

VENV=${VENV:-.venv}
PYTHON=${PYTHON:-python3}
STAMP="$VENV/.dynnav-installed"
is_root() { [ "$(id -u)" = 0 ]; }
apt_updated=
apt_install() {
  if [ -z "$apt_updated" ]; then apt-get update -qq; apt_updated=1; fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"
}

# --- Python 3.11 with venv -------------------------------------------------------------
if ! command -v "$PYTHON" >/dev/null 2>&1 || ! "$PYTHON" -c 'import sys; assert sys.version_info[:2] == (3, 11)' 2>/dev/null; then
  if is_root && command -v apt-get >/dev/null; then apt_install python3 python3-venv python3-dev; PYTHON=python3
  else echo "dynnav needs Python 3.11 (Debian 12: apt-get install python3 python3-venv); set PYTHON=/path/to/python3.11" >&2; exit 1; fi
fi
if [ -d "$VENV" ] && ! "$VENV/bin/python" -m pip --version >/dev/null 2>&1; then
  echo "$VENV is broken (no working pip): recreating it."
  rm -rf "$VENV"
fi
if [ ! -x "$VENV/bin/python" ]; then
  if ! "$PYTHON" -m venv "$VENV" 2>/dev/null; then
    rm -rf "$VENV"
    if is_root && command -v apt-get >/dev/null; then apt_install python3-venv; "$PYTHON" -m venv "$VENV"
    else echo "python3 -m venv failed; as root run: apt-get install -y python3-venv" >&2; exit 1; fi
  fi
fi

# --- Python packages: torch (CPU build) first, so nothing pulls a CUDA build -----------
if [ ! -f "$STAMP" ] || [ pyproject.toml -nt "$STAMP" ]; then
  "$VENV/bin/python" -m pip install -q --upgrade pip
  "$VENV/bin/python" -m pip install -q torch==2.13.0
  # torch==2.13.0 named again: no extra (SB3 in "bench") can make pip replace the CPU build
  "$VENV/bin/python" -m pip install -q -e ".[test,docs,bench,tensorboard]" torch==2.13.0
  rm -f "$VENV/.dynnav-vulkan-ok"
  touch "$STAMP"
fi

# --- Vulkan: SAPIEN must be able to create a render device ------------------------------
if [ ! -f "$VENV/.dynnav-vulkan-ok" ]; then
  if ! "$VENV/bin/python" -m dynnav_tasks.vulkan 2>/tmp/dynnav-vulkan.err; then
    if is_root && command -v apt-get >/dev/null; then
      echo "No working Vulkan device: installing Mesa's lavapipe from bookworm-backports."
      echo 'deb http://deb.debian.org/debian bookworm-backports main' > /etc/apt/sources.list.d/bookworm-backports.list
      apt-get update -qq
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers libvulkan1
      "$VENV/bin/python" -m dynnav_tasks.vulkan
    else
      cat /tmp/dynnav-vulkan.err >&2
      exit 1
    fi
  fi
  touch "$VENV/.dynnav-vulkan-ok"
fi
