"""Shared by ``run`` and ``sitl``: the recording and live-view options and the recorder they open."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any, Mapping

from ..errors import Dip3dError

__all__ = ["add_record_arguments", "open_recorder", "close_recorder"]


def add_record_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --view, --view-token, --foxglove and --video."""
    parser.add_argument("--view", metavar="HOST:PORT", default=None,
                        help="serve the pilot's live page (GET / ; e.g. a BlueOS Cockpit iframe) on this address "
                             "(PORT alone binds 127.0.0.1)")
    parser.add_argument("--view-token", metavar="FILE|auto", default=None,
                        help="offer ENABLE/STOP on the live page, allowed only with this token (a file's first "
                             "line, or 'auto' = a new one printed at start); without it the page is read-only")
    parser.add_argument("--foxglove", metavar="HOST:PORT", default=None,
                        help="serve the run record's channels live over Foxglove's WebSocket protocol "
                             "(PORT alone binds 127.0.0.1)")
    parser.add_argument("--video", action="store_true",
                        help="also write the annotated left video (annotated.mp4) to the output folder")


def open_recorder(args: argparse.Namespace, mcap_path: Path, params: Mapping[str, Any], meta: Mapping[str, Any],
                  rig: Any = None, command: str = "run", **writer_options: Any):
    """Return (RunRecorder, lines to print on stderr) for ``mcap_path`` with ``mav.tlog`` beside it.

    Raises:
        Dip3dError: a bad address, token file or an unusable output file.
    """
    from ..record.recorder import TLOG_NAME, VIDEO_NAME, RunRecorder
    from ..view.server import load_token, parse_address

    lines, view, live = [], None, None
    if args.view_token and not args.view:
        raise Dip3dError("--view-token: needs --view HOST:PORT")
    try:
        if args.view:
            from ..view.server import ViewServer

            token, where = load_token(args.view_token)
            host, port = parse_address(args.view, "--view")
            view = ViewServer(host, port, token, title=f"dip3d-vehicle {command}")
            lines.append(f"{command}: live view at {view.url} ({'operator control, token ' + where if token else 'read-only'})")
            if token and where == "generated":
                lines.append(f"{command}: live view operator token: {token}")
        if args.foxglove:
            from ..view.foxglove_live import FoxgloveLive

            host, port = parse_address(args.foxglove, "--foxglove")
            live = FoxgloveLive(host, port, name=f"dip3d-vehicle {command}")
            lines.append(f"{command}: Foxglove WebSocket at {live.url}")
        wants_video = getattr(args, "video", False) or bool(params.get("runlog.annotated_video", False))
        video = mcap_path.parent / VIDEO_NAME if wants_video else None
        recorder = RunRecorder(mcap_path, params, meta, rig=rig, tlog_path=mcap_path.parent / TLOG_NAME,
                               video_path=video, view=view, foxglove=live, **writer_options)
    except BaseException:
        for server in (view, live):
            if server is not None:
                server.close()
        raise
    recorder.servers = [s for s in (view, live) if s is not None]
    return recorder, lines


def close_recorder(recorder: Any) -> None:
    """Close the recorder and stop its servers (the live view prints its operator-request counts)."""
    try:
        recorder.close()
    finally:
        for server in getattr(recorder, "servers", []):
            server.close()
            if hasattr(server, "refused_reasons"):
                print(f"live view: {server.counts['accepted']} operator requests accepted, {server.counts['refused']} "
                      f"refused {server.refused_reasons or ''}".rstrip(), file=sys.stderr, flush=True)
