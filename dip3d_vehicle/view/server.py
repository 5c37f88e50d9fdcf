"""The pilot's live view: one self-contained web page served by the controller (no CDN, no internet).

    GET  /            the page (HTML + inline CSS/JS; fits a BlueOS Cockpit iframe widget)
    GET  /state.json  mission state, engaged, hold reason, last story lines, chosen target and its
                      probability, link status, refused-request count
    GET  /frame.jpg   the newest left image with the controller's overlay (arm, pointing ray,
                      candidates with probability, target, tracker box), JPEG, polled by the page
    POST /enable      the operator's enable  } only with ``--view-token``: the request must carry
    POST /stop        withdraw the enable    } ``X-Dip3d-Token: TOKEN``; every refused one is counted

Read-only by default: without a token configured, every POST is refused (403) and counted. It binds
to 127.0.0.1 unless an address is given. Requests are queued; the controller applies them on its
own loop thread (``RunRecorder.tick``), never from the server's thread.
"""

from __future__ import annotations

import hmac
import json
import secrets
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from ..errors import Dip3dError
from ..record.overlay import draw_overlay

__all__ = ["ViewServer", "parse_address", "load_token", "PAGE"]

MAX_WIDTH_PX = 960
FRAME_MIN_PERIOD_S = 0.2  # render at most 5 images a second whatever the number of viewers


def parse_address(text: str, option: str = "--view") -> tuple[str, int]:
    """Return (host, port) of ``HOST:PORT`` or ``PORT`` (host 127.0.0.1).

    Raises:
        Dip3dError: malformed address or port out of range.
    """
    host, sep, port = str(text).rpartition(":")
    host = host if sep else "127.0.0.1"
    if not port.isdigit() or not 0 <= int(port) < 65536 or (sep and not host):
        raise Dip3dError(f"{option} {text!r}: expected HOST:PORT or PORT (0-65535)")
    return host.strip("[]"), int(port)


def load_token(spec: str | None) -> tuple[str | None, str]:
    """Return (token, where) for ``--view-token``: None -> no control; ``auto`` -> new random token;
    else the first line of that file (at least 16 characters).

    Raises:
        Dip3dError: the file is missing, unreadable or its token too short.
    """
    if spec is None:
        return None, "read-only"
    if spec == "auto":
        return secrets.token_urlsafe(18), "generated"
    try:
        token = Path(spec).read_text().strip().splitlines()[0].strip()
    except (OSError, IndexError) as exc:
        raise Dip3dError(f"--view-token {spec}: cannot read a token ({getattr(exc, 'strerror', None) or 'empty file'})") from None
    if len(token) < 16:
        raise Dip3dError(f"--view-token {spec}: token is {len(token)} characters, expected at least 16")
    return token, f"from {spec}"


class ViewServer:
    """Serve the live page on (host, port) from a daemon thread.

    Args:
        host, port: where to listen (port 0 = any free port; see ``port``).
        token: the operator token enabling POST /enable and /stop, or None (read-only).
        title: shown in the page's header.

    Raises:
        Dip3dError: the address cannot be bound.
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 8090, token: str | None = None,
                 title: str = "dip3d-vehicle") -> None:
        self.token, self.title = token, title
        self._lock = threading.Lock()
        self._state: dict[str, Any] = {"state": "starting", "story": [], "target": None}
        self._frame: tuple[np.ndarray, dict | None, int] | None = None
        self._frame_version = 0
        self._jpeg: tuple[int, bytes] | None = None
        self._jpeg_at = 0.0
        self._requests: list[str] = []
        self.counts = {"refused": 0, "accepted": 0, "pages": 0, "frames": 0, "states": 0}
        self.refused_reasons: dict[str, int] = {}
        try:
            self._httpd = ThreadingHTTPServer((host, port), _handler(self))
        except OSError as exc:
            raise Dip3dError(f"--view {host}:{port}: cannot listen ({exc.strerror})") from None
        self._httpd.daemon_threads = True
        self.host, self.port = self._httpd.server_address[:2]
        self._thread = threading.Thread(target=self._httpd.serve_forever, name="dip3d-view", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """The page's address."""
        return f"http://{self.host}:{self.port}/"

    # -- fed by the recorder -----------------------------------------------------------------
    def update(self, **state: Any) -> None:
        """Merge the controller's latest state (state, engaged, story, link, ...)."""
        with self._lock:
            self._state.update(state)

    def set_frame(self, left: np.ndarray, overlay: dict | None, index: int) -> None:
        """Offer the newest left image with its overlay (rendered only when a viewer asks)."""
        with self._lock:
            self._frame = (left, overlay, int(index))
            self._frame_version += 1
            if overlay is not None:
                target = overlay.get("target")
                self._state["target"] = None if target is None else {"px": target["px"], "p": target.get("p"),
                                                                     "method": target.get("method")}
                self._state["status"] = overlay.get("status")
                self._state["candidates"] = len(overlay.get("candidates") or [])

    def take_requests(self) -> list[str]:
        """Return and clear the operator requests accepted since the last call ("enable"/"stop")."""
        with self._lock:
            out, self._requests = self._requests, []
        return out

    # -- served ---------------------------------------------------------------------------------
    def state_json(self) -> bytes:
        """The page's state document."""
        with self._lock:
            doc = dict(self._state, control=self.token is not None, frame_index=None if self._frame is None
                       else self._frame[2], requests={k: self.counts[k] for k in ("refused", "accepted")})
        return json.dumps(doc, default=str).encode()

    def frame_jpeg(self) -> bytes | None:
        """The newest annotated left image as JPEG (cached; re-rendered at most every 0.2 s)."""
        with self._lock:
            frame, version = self._frame, self._frame_version
            cached = self._jpeg
            state = self._state.get("state", "")
        if frame is None:
            return None
        if cached is not None and (cached[0] == version or time.monotonic() - self._jpeg_at < FRAME_MIN_PERIOD_S):
            return cached[1]
        left, overlay, index = frame
        img = draw_overlay(left, overlay, f"{state}  frame {index}")
        if img.shape[1] > MAX_WIDTH_PX:
            scale = MAX_WIDTH_PX / img.shape[1]
            img = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
        ok, data = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, 80])
        if not ok:
            return None
        with self._lock:
            self._jpeg, self._jpeg_at = (version, data.tobytes()), time.monotonic()
        return data.tobytes()

    def operator_request(self, action: str, token: str | None) -> tuple[int, str]:
        """Check and queue one operator request; return (HTTP status, message)."""
        if self.token is None:
            return self._refuse("read-only", "read-only view: started without --view-token")
        if not token or not hmac.compare_digest(token.encode(), self.token.encode()):
            return self._refuse("bad token" if token else "no token", "missing or wrong X-Dip3d-Token")
        with self._lock:
            self._requests.append(action)
            self.counts["accepted"] += 1
        return 202, f"{action} queued"

    def _refuse(self, reason: str, text: str) -> tuple[int, str]:
        with self._lock:
            self.counts["refused"] += 1
            self.refused_reasons[reason] = self.refused_reasons.get(reason, 0) + 1
        return 403, text

    def close(self) -> None:
        """Stop serving."""
        self._httpd.shutdown()
        self._httpd.server_close()


def _handler(view: ViewServer) -> type:
    class Handler(BaseHTTPRequestHandler):
        server_version = "dip3d-view/1"

        def log_message(self, *args: Any) -> None:  # quiet: the console belongs to the story
            pass

        def _send(self, status: int, body: bytes, ctype: str) -> None:
            self.send_response(status)
            self.send_header("Content-Type", ctype)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def do_GET(self) -> None:  # noqa: N802 - http.server's name
            path = self.path.split("?", 1)[0]
            if path in ("/", "/index.html"):
                view.counts["pages"] += 1
                self._send(200, PAGE.replace("{{TITLE}}", view.title).encode(), "text/html; charset=utf-8")
            elif path == "/state.json":
                view.counts["states"] += 1
                self._send(200, view.state_json(), "application/json")
            elif path == "/frame.jpg":
                data = view.frame_jpeg()
                if data is None:
                    self._send(404, b"no frame yet", "text/plain")
                else:
                    view.counts["frames"] += 1
                    self._send(200, data, "image/jpeg")
            else:
                self._send(404, b"not found", "text/plain")

        def do_POST(self) -> None:  # noqa: N802
            path = self.path.split("?", 1)[0]
            length = int(self.headers.get("Content-Length") or 0)
            if length:
                self.rfile.read(min(length, 4096))
            if path not in ("/enable", "/stop"):
                self._send(404, b"not found", "text/plain")
                return
            status, text = view.operator_request(path[1:], self.headers.get("X-Dip3d-Token"))
            self._send(status, text.encode(), "text/plain")

    return Handler


PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>{{TITLE}} live view</title>
<style>
 body{margin:0;background:#10151c;color:#e6edf3;font:14px/1.4 system-ui,sans-serif}
 header{display:flex;gap:12px;align-items:center;padding:6px 10px;background:#1b2430}
 .pill{padding:2px 8px;border-radius:10px;background:#30363d;font-weight:600}
 .ok{background:#1f6f3f}.warn{background:#8a5a00}.bad{background:#8b1e1e}
 main{display:flex;flex-wrap:wrap;gap:10px;padding:10px}
 #img{max-width:100%;width:640px;background:#000;border:1px solid #30363d}
 section{flex:1;min-width:260px}
 table{border-collapse:collapse;width:100%}td{padding:2px 6px;border-bottom:1px solid #222b36;vertical-align:top}
 td:first-child{color:#8b949e;white-space:nowrap}
 #story{font:12px/1.35 ui-monospace,monospace;white-space:pre-wrap;background:#0b0f14;padding:6px;max-height:220px;overflow:auto}
 button{font-weight:700;padding:6px 14px;margin-right:6px;border:0;border-radius:4px;cursor:pointer}
 #enable{background:#1f6f3f;color:#fff}#stop{background:#b62324;color:#fff}
</style></head><body>
<header><b>{{TITLE}}</b><span id="state" class="pill">connecting</span><span id="engaged" class="pill">-</span>
<span id="linkpill" class="pill">link ?</span><span id="t"></span></header>
<main>
<img id="img" alt="live left image with the controller's overlay">
<section>
<table>
<tr><td>mission state</td><td id="s_state">-</td></tr>
<tr><td>perception</td><td id="s_status">-</td></tr>
<tr><td>chosen target</td><td id="s_target">-</td></tr>
<tr><td>probability</td><td id="s_p">-</td></tr>
<tr><td>not engaged because</td><td id="s_hold">-</td></tr>
<tr><td>autopilot</td><td id="s_ap">-</td></tr>
<tr><td>ground station</td><td id="s_gcs">-</td></tr>
</table>
<div id="control" hidden><p>Operator: <input id="token" type="password" placeholder="token" size="14">
<button id="enable">ENABLE</button><button id="stop">STOP</button> <span id="ctl"></span></p></div>
<h4>story</h4><div id="story"></div>
</section></main>
<script>
"use strict";
const $ = (id) => document.getElementById(id);
let frameBusy = false;
function cls(el, c){ el.className = "pill " + c; }
function fmt(v, d){ return (v === null || v === undefined) ? "-" : (typeof v === "number" ? v.toFixed(d) : String(v)); }
async function poll(){
  try {
    const r = await fetch("state.json", {cache: "no-store"}); const s = await r.json();
    $("state").textContent = s.state; $("s_state").textContent = s.state + (s.arrived ? " (arrived)" : "");
    $("engaged").textContent = s.engaged ? "ENGAGED" : "not engaged"; cls($("engaged"), s.engaged ? "ok" : "warn");
    $("t").textContent = "t=" + fmt(s.t_s, 1) + " s";
    $("s_status").textContent = fmt(s.status) + (s.candidates !== undefined ? "  (" + s.candidates + " candidates)" : "");
    $("s_target").textContent = s.target ? "(" + s.target.px.map(v => v.toFixed(0)).join(", ") + ") px " + (s.target.method || "") : "none";
    $("s_p").textContent = s.target ? fmt(s.target.p, 2) : "-";
    $("s_hold").textContent = s.hold_reason || "-";
    const l = s.link || {};
    $("s_ap").textContent = (l.mode || "?") + (l.armed ? " armed" : " disarmed") + ", heard " + fmt(l.autopilot_age_s, 2) + " s ago";
    $("s_gcs").textContent = "heard " + fmt(l.gcs_age_s, 2) + " s ago; operator enable " + (l.operator_enabled ? "on" : "off");
    const alive = l.autopilot_age_s !== null && l.autopilot_age_s !== undefined && l.autopilot_age_s < 1.5;
    $("linkpill").textContent = alive ? "link ok" : "link LOST"; cls($("linkpill"), alive ? "ok" : "bad");
    $("story").textContent = (s.story || []).join("\\n");
    $("control").hidden = !s.control;
  } catch (e) { $("state").textContent = "no connection"; cls($("state"), "bad"); }
}
function frame(){
  if (frameBusy) return; frameBusy = true;
  const img = new Image();
  img.onload = () => { $("img").src = img.src; frameBusy = false; };
  img.onerror = () => { frameBusy = false; };
  img.src = "frame.jpg?n=" + Date.now();
}
async function operator(action){
  const r = await fetch(action, {method: "POST", headers: {"X-Dip3d-Token": $("token").value}});
  $("ctl").textContent = action + ": " + r.status + " " + await r.text();
}
$("enable").onclick = () => operator("enable"); $("stop").onclick = () => operator("stop");
poll(); frame(); setInterval(poll, 500); setInterval(frame, 250);
</script></body></html>
"""
