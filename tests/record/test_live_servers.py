"""The live servers: the Foxglove WebSocket server answered by a real client (channels advertised,
messages received), and the pilot's page (state, image, read-only by default, token-gated control)."""

from __future__ import annotations

import asyncio
import json
import struct
import time
import urllib.error
import urllib.request

import numpy as np
import pytest

from dip3d_vehicle.errors import Dip3dError
from dip3d_vehicle.record.recorder import RunRecorder
from dip3d_vehicle.view.server import ViewServer, load_token, parse_address

websockets = pytest.importorskip("websockets", reason="the test client needs the 'websockets' package (test extra)")


async def _foxglove_client(url: str, want: set[str], publish) -> tuple[dict, dict]:
    """Connect, collect advertised channels, subscribe to ``want``, return (channels, messages)."""
    async with websockets.connect(url, subprotocols=["foxglove.sdk.v1"], compression=None) as ws:
        channels: dict[str, dict] = {}
        deadline = time.monotonic() + 10
        while not want <= set(channels) and time.monotonic() < deadline:
            msg = await asyncio.wait_for(ws.recv(), 5)
            if isinstance(msg, str):
                doc = json.loads(msg)
                if doc.get("op") == "advertise":
                    channels.update({c["topic"]: c for c in doc["channels"]})
        subs = {i + 1: channels[t]["id"] for i, t in enumerate(sorted(want))}
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": s, "channelId": c}
                                                                      for s, c in subs.items()]}))
        await asyncio.sleep(0.3)
        publish()
        got: dict[str, list] = {}
        topic_of = {s: next(t for t, c in channels.items() if c["id"] == cid) for s, cid in subs.items()}
        deadline = time.monotonic() + 10
        while sum(len(v) for v in got.values()) < len(want) and time.monotonic() < deadline:
            msg = await asyncio.wait_for(ws.recv(), 5)
            if isinstance(msg, bytes) and msg[0] == 1:  # MessageData: op, subscription id, log time, payload
                sub, log_time = struct.unpack_from("<IQ", msg, 1)
                got.setdefault(topic_of[sub], []).append((log_time, msg[13:]))
        return channels, got


def test_foxglove_websocket_server_answers_a_client(tmp_path):
    from dip3d_vehicle.view.foxglove_live import FoxgloveLive

    live = FoxgloveLive("127.0.0.1", 0, topics=("/story", "/servo", "/camera/left/image"))
    recorder = RunRecorder(tmp_path / "run.mcap", None, {"command": "test"}, foxglove=live, keep_images_every=1)
    image = np.random.default_rng(0).integers(0, 256, (48, 64, 3), dtype=np.uint8)

    def publish() -> None:
        recorder.event("t=1.00 hello from the controller")
        recorder.mcap.publish_json("/servo", {"t_s": 1.0, "pixel_error_px": 12.5})
        recorder.images(0, image, image)

    try:
        channels, got = asyncio.run(_foxglove_client(live.url, {"/story", "/servo", "/camera/left/image"}, publish))
    finally:
        recorder.close()
        live.close()
    print(f"\nadvertised: {sorted(channels)}; received: {{{', '.join(f'{k}: {len(v)}' for k, v in got.items())}}}")
    assert channels["/story"]["schemaName"] == "foxglove.Log" and channels["/story"]["encoding"] == "protobuf"
    assert channels["/servo"]["schemaName"] == "dip3d.Servo" and channels["/servo"]["encoding"] == "json"
    assert json.loads(got["/servo"][0][1])["pixel_error_px"] == 12.5
    assert b"hello from the controller" in got["/story"][0][1]
    assert got["/camera/left/image"][0][1].count(b"JFIF") == 1  # the JPEG inside the CompressedImage


def _get(url: str) -> tuple[int, bytes, str]:
    with urllib.request.urlopen(url, timeout=5) as r:
        return r.status, r.read(), r.headers.get("Content-Type", "")


def _post(url: str, token: str | None = None) -> int:
    req = urllib.request.Request(url, data=b"", method="POST", headers={"X-Dip3d-Token": token} if token else {})
    try:
        with urllib.request.urlopen(req, timeout=5) as r:
            return r.status
    except urllib.error.HTTPError as exc:
        return exc.code


def test_view_is_read_only_by_default_and_serves_state_and_image():
    view = ViewServer("127.0.0.1", 0)
    try:
        assert view.host == "127.0.0.1"
        status, page, ctype = _get(view.url)
        assert status == 200 and ctype.startswith("text/html") and b"<script>" in page
        assert b"http://" not in page and b"https://" not in page  # nothing fetched from the internet
        view.update(state="servo", engaged=True, story=["t=1.00 hello"])
        view.set_frame(np.zeros((1200, 1600, 3), np.uint8), {"status": "ok", "candidates": [],
                                                              "target": {"px": [800.0, 600.0], "p": 0.91}}, 7)
        state = json.loads(_get(view.url + "state.json")[1])
        assert state["state"] == "servo" and state["target"]["p"] == 0.91 and state["control"] is False
        status, jpeg, ctype = _get(view.url + "frame.jpg")
        assert status == 200 and ctype == "image/jpeg" and jpeg[:2] == b"\xff\xd8"
        assert [_post(view.url + a, t) for a, t in (("enable", None), ("stop", "x" * 20))] == [403, 403]
        assert view.counts["refused"] == 2 and view.take_requests() == []
    finally:
        view.close()


def test_view_control_needs_the_token():
    token = "s3cret-token-0123456789"
    view = ViewServer("127.0.0.1", 0, token=token)
    try:
        codes = [_post(view.url + "enable"), _post(view.url + "enable", "wrong-token-0123456789"),
                 _post(view.url + "stop", token[:-1]), _post(view.url + "enable", token), _post(view.url + "stop", token)]
        assert codes == [403, 403, 403, 202, 202]
        assert view.counts == dict(view.counts, refused=3, accepted=2)
        assert view.refused_reasons == {"no token": 1, "bad token": 2}
        assert view.take_requests() == ["enable", "stop"] and view.take_requests() == []
        assert json.loads(_get(view.url + "state.json")[1])["requests"] == {"refused": 3, "accepted": 2}
    finally:
        view.close()


def test_addresses_and_tokens(tmp_path):
    assert parse_address("8090") == ("127.0.0.1", 8090)
    assert parse_address("0.0.0.0:8090") == ("0.0.0.0", 8090)
    for bad in ("", "host:", ":80", "x:70000", "abc"):
        with pytest.raises(Dip3dError, match="--view"):
            parse_address(bad)
    assert load_token(None) == (None, "read-only")
    token, where = load_token("auto")
    assert len(token) >= 16 and where == "generated"
    (tmp_path / "short").write_text("abc\n")
    with pytest.raises(Dip3dError, match="at least 16"):
        load_token(str(tmp_path / "short"))
    (tmp_path / "ok").write_text("a-long-enough-operator-token\n")
    assert load_token(str(tmp_path / "ok"))[0] == "a-long-enough-operator-token"
    with pytest.raises(Dip3dError, match="cannot read"):
        load_token(str(tmp_path / "missing"))


def test_command_line_errors(tmp_path, capsys):
    from dip3d_vehicle.cli import main

    assert main(["sitl", "--out", str(tmp_path), "--view-token", "auto"]) == 2
    assert "--view-token: needs --view HOST:PORT" in capsys.readouterr().err
    assert main(["sitl", "--out", str(tmp_path), "--view", "host:"]) == 2
    assert "--view 'host:': expected HOST:PORT" in capsys.readouterr().err
