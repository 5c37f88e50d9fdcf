"""Opening a MAVLink 2 connection by URL, and the second encoder that speaks as the ground station.

pymavlink picks MAVLink 1 or 2 from a process-wide environment variable and switches on the first
byte it receives; signing needs MAVLink 2 from the first packet we send, so each connection here
gets its own MAVLink 2 encoder/parser (no global side effects).
"""

from __future__ import annotations

from typing import Any

from pymavlink import mavutil
from pymavlink.dialects.v20 import ardupilotmega as mavlink2

from ..errors import LinkError

__all__ = ["mavlink2", "open_connection", "gcs_encoder", "url_kind"]


def url_kind(url: str) -> str:
    """Return "udp", "tcp", "tcpin" or "serial" for a connection URL; raise LinkError when malformed."""
    if url.startswith(("udpin:", "udpout:", "udp:", "udpbcast:")):
        kind = "udp"
    elif url.startswith("tcpin:"):
        kind = "tcpin"
    elif url.startswith("tcp:"):
        kind = "tcp"
    elif url.startswith(("/", "COM", "com")):
        return "serial"
    else:
        raise LinkError(f"link.url = {url!r}: expected udpin:HOST:PORT, udpout:HOST:PORT, tcp:HOST:PORT, "
                        f"tcpin:HOST:PORT or a serial device path")
    host_port = url.split(":", 1)[1]
    host, sep, port = host_port.rpartition(":")
    if not sep or not host or not port.isdigit() or not 0 <= int(port) < 65536:
        raise LinkError(f"link.url = {url!r}: expected HOST:PORT after the scheme")
    return kind


def open_connection(url: str, system_id: int, component_id: int, baud: int = 115200) -> Any:
    """Open a non-blocking pymavlink connection speaking MAVLink 2 as (system_id, component_id).

    Args:
        url: ``udpin:``/``udpout:``/``tcp:``/``tcpin:`` HOST:PORT, or a serial device (``DEV[,BAUD]``).
        system_id: our MAVLink system id.
        component_id: our MAVLink component id.
        baud: serial baud rate when the URL gives none.

    Returns:
        The pymavlink ``mavfile``; its ``mav`` is a MAVLink 2 encoder/parser.

    Raises:
        LinkError: malformed URL, or the port/device cannot be opened (message names the URL).
    """
    kind = url_kind(url)
    device, serial_baud = url, baud
    if kind == "serial" and "," in url:
        device, _, b = url.partition(",")
        if not b.isdigit():
            raise LinkError(f"link.url = {url!r}: baud after ',' must be a number")
        serial_baud = int(b)
    try:
        conn = mavutil.mavlink_connection(device, baud=serial_baud, source_system=system_id,
                                          source_component=component_id, retries=0, autoreconnect=False)
    except (OSError, ValueError, ImportError) as exc:
        raise LinkError(f"link.url = {url!r}: cannot open ({exc})") from None
    use_mavlink2(conn)
    return conn


def use_mavlink2(conn: Any) -> None:
    """Give ``conn`` its own MAVLink 2 encoder/parser and stop pymavlink's version auto-switch."""
    mav = mavlink2.MAVLink(conn, srcSystem=conn.source_system, srcComponent=conn.source_component)
    mav.robust_parsing = True
    conn.mav = mav
    conn.WIRE_PROTOCOL_VERSION = "2.0"
    conn.first_byte = False


def gcs_encoder(conn: Any, gcs_system_id: int, component_id: int) -> Any:
    """Return a MAVLink 2 encoder writing on ``conn`` with the ground station's system id.

    Used ONLY for MANUAL_CONTROL (ArduSub accepts it only from SYSID_MYGCS). It shares the
    connection's signing state, so its packets are signed with the same key and timestamps.
    """
    enc = mavlink2.MAVLink(conn, srcSystem=gcs_system_id, srcComponent=component_id)
    enc.signing = conn.mav.signing
    return enc
