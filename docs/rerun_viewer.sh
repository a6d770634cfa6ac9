#!/usr/bin/env bash
# Screenshot a Rerun recording (.rrd) as the Rerun *web* viewer shows it, on a headless
# Linux machine without a display or GPU. This is a docs tool; the tests don't run it.
#
#   docs/rerun_viewer.sh RECORDING.rrd OUT.png [WAIT_S]
#
# e.g.
#   .venv/bin/python -m fluidsim_envs.wrappers.rerun_layout record \
#       fluidsim/PaperAirplane-v0 /tmp/dart.rrd
#   docs/rerun_viewer.sh /tmp/dart.rrd docs/rerun_viewer.png
#
# How: `rerun RECORDING --serve-web` serves the web viewer over HTTP and the recording over
# gRPC; headless Chromium opens http://127.0.0.1:$WEB_PORT/?url=rerun+http://127.0.0.1:$GRPC_PORT/proxy
# and, after WAIT_S seconds (default 40) for the viewer to start and load the data, saves
# a screenshot (the time cursor is then at the end of the recording). The PNG is then
# quantized to 256 colors to keep it small.
#
# Needs (tested with rerun-sdk 0.41.0, Chromium 150 on Debian 12):
#   - the project's venv with rerun-sdk (RERUN, default .venv/bin/rerun);
#   - Debian's chromium and chromium-driver: apt-get install -y chromium chromium-driver;
#   - a Python with selenium and pillow, kept out of the project's venv (PY, default
#     /tmp/shot/venv/bin/python; made with `python3 -m venv` + pip if missing).
# Rendering: WebGL 2 on SwiftShader (Chromium's CPU renderer): `&renderer=webgl` is needed,
# since the default WebGPU path crashes on SwiftShader in Rerun 0.41 ("createBuffer failed,
# size (33554432) is too large for the implementation when mappedAtCreation == true").
# The viewer then shows a "Software rasterizer" warning in its top bar; that is expected.
# Its requests to the internet (analytics, version check, fonts) fail harmlessly offline.
set -euo pipefail

RRD=${1:?usage: $0 RECORDING.rrd OUT.png [WAIT_S]}
OUT=${2:?usage: $0 RECORDING.rrd OUT.png [WAIT_S]}
WAIT_S=${3:-40}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RERUN=${RERUN:-$ROOT/.venv/bin/rerun}
PY=${PY:-/tmp/shot/venv/bin/python}
WEB_PORT=${WEB_PORT:-9090}    # HTTP: the viewer's page and wasm
GRPC_PORT=${GRPC_PORT:-9876}  # gRPC proxy that streams the recording to the viewer
SIZE=${SIZE:-1600x1000}       # browser viewport, CSS pixels

if [ ! -x "$PY" ]; then
    python3 -m venv "$(dirname "$(dirname "$PY")")"
    "$PY" -m pip install -q selenium pillow
fi
command -v chromium >/dev/null && command -v chromedriver >/dev/null ||
    { echo "needs: apt-get install -y chromium chromium-driver" >&2; exit 1; }

# The rerun server, in its own process group: bin/rerun is a Python wrapper around the
# real binary, so killing the wrapper's pid alone would leave the server running.
LOG=$(mktemp /tmp/rerun-serve.XXXXXX.log)
setsid "$RERUN" "$RRD" --serve-web --bind 127.0.0.1 \
    --web-viewer-port "$WEB_PORT" --port "$GRPC_PORT" >"$LOG" 2>&1 &
SERVER=$!
trap 'kill -- -$SERVER 2>/dev/null || true' EXIT
for _ in $(seq 60); do
    grep -q "Hosting a web-viewer" "$LOG" && break
    grep -q "Address already in use" "$LOG" &&
        { echo "port in use (set WEB_PORT / GRPC_PORT):" >&2; cat "$LOG" >&2; exit 1; }
    sleep 0.5
done
grep -q "Hosting a web-viewer" "$LOG" || { cat "$LOG" >&2; exit 1; }

URL="http://127.0.0.1:$WEB_PORT/?url=rerun%2Bhttp%3A%2F%2F127.0.0.1%3A$GRPC_PORT%2Fproxy&renderer=webgl"
"$PY" - "$URL" "$OUT" "$WAIT_S" "$SIZE" <<'EOF'
import sys, tempfile, time
from PIL import Image
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

url, out, wait_s, size = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
w, h = map(int, size.split("x"))
opts = webdriver.ChromeOptions()
opts.binary_location = "/usr/bin/chromium"
for arg in [
    "--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
    f"--window-size={w},{h}",
    "--user-data-dir=" + tempfile.mkdtemp(prefix="rr-chrome-"),  # fresh: no saved viewer state
]:
    opts.add_argument(arg)
d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
try:
    # the viewport itself at w x h (--window-size also counts the window's frame)
    d.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                      {"width": w, "height": h, "deviceScaleFactor": 1, "mobile": False})
    d.get(url)
    time.sleep(wait_s)  # start the wasm app, stream the recording, lay out the blueprint
    crashed = d.execute_script("return document.body.innerText.includes('Rerun has crashed')")
    d.save_screenshot(out)
    if crashed:
        sys.exit(f"the viewer crashed; see {out}")
finally:
    d.quit()
Image.open(out).convert("RGB").quantize(256, dither=Image.Dither.NONE).save(out, optimize=True)
print(f"{out}: {Image.open(out).size}")
EOF
ls -l "$OUT"
