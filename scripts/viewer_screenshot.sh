#!/usr/bin/env bash
# Screenshot of the Rerun viewer showing a recording, rendered headless (Xvfb + Mesa's lavapipe).
#   bash scripts/viewer_screenshot.sh runs/visual.rrd docs/images/rerun-viewer.png
# Needs Debian's xvfb (apt-get install -y xvfb xauth).
set -euo pipefail
rrd=${1:?usage: viewer_screenshot.sh RECORDING.rrd OUT.png}
out=${2:?usage: viewer_screenshot.sh RECORDING.rrd OUT.png}
cd "$(dirname "$0")/.."
command -v xvfb-run >/dev/null || { echo "xvfb-run not found: apt-get install -y xvfb xauth" >&2; exit 1; }
tmp=$(mktemp --suffix .png)
xvfb-run -a -s "-screen 0 1600x900x24" .venv/bin/rerun "$rrd" --screenshot-to "$tmp" --window-size 1600x900
.venv/bin/python -c "import sys; from PIL import Image; Image.open(sys.argv[1]).resize((1600, 900), Image.LANCZOS).save(sys.argv[2], optimize=True)" "$tmp" "$out"
rm -f "$tmp"
echo "wrote $out"
