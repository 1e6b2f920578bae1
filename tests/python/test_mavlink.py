"""uascma.mavlink: start_sitl starts `uascma sitl`, which answers a peer on loopback with MAVLink v2 frames."""
import os
import socket

import pytest

import uascma
from uascma.mavlink import start_companion, start_sitl

from conftest import SOURCE_DIR, example


def ground_station_heartbeat():
    # The first frame of tests/data/mavlink/heartbeat-command-item.bin: a GCS HEARTBEAT (21 bytes).
    with open(os.path.join(SOURCE_DIR, "tests", "data", "mavlink", "heartbeat-command-item.bin"), "rb") as f:
        return f.read(21)


def test_a_started_sitl_answers_a_peer_with_its_heartbeat(cli):
    with start_sitl(example("scenario-1.yaml"), wait_for_start=True) as sitl, \
            socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as peer:
        assert sitl.port > 0 and sitl.address == f"udp:127.0.0.1:{sitl.port}"
        peer.settimeout(5.0)
        peer.sendto(ground_station_heartbeat(), ("127.0.0.1", sitl.port))
        datagram, _ = peer.recvfrom(65536)  # on the ground it streams once a wall second
        assert datagram[0] == 0xFD  # a MAVLink v2 frame
        assert datagram[5] == 1  # from system 1
        message_id = datagram[7] | datagram[8] << 8 | datagram[9] << 16
        assert message_id == 0  # HEARTBEAT first
        assert datagram[10 + 4] == 13  # MAV_TYPE_HEXAROTOR, after custom_mode (wire order)
    assert sitl.process.poll() is not None  # stopped on leaving the block


def test_a_refused_argument_is_an_input_error(cli):
    with pytest.raises(uascma.InputError, match="--speed"):
        start_sitl(example("scenario-1.yaml"), speed=1e6)


def test_a_companion_flies_scenario_2_as_the_in_process_cma(cli, tmp_path):
    # Scenario II (§5.5.2) with the CMA on the link: LandPract on the spall, LandASAP after the jam, the landing at the
    # site the in-process CMA lands at (docs/mavlink.md#what-the-companion-reproduces).
    log = tmp_path / "decisions.csv"
    with start_companion(example("scenario-2.yaml"), log=log) as cma, \
            start_sitl(example("scenario-2.yaml"), speed=50, linger_s=1, companion=cma) as sitl:
        summary = sitl.wait(timeout=120)
        cma.wait(timeout=60)
    assert summary.startswith("emergency_landing (landed at the emergency site roof block 2,0 lot n/0)")
    rows = log.read_text().splitlines()
    taken = [row.split('",')[1].split(",")[1] for row in rows[1:] if '",' in row]
    assert [action for action in taken if action not in ("NoOp", "")] == ["LandPract", "LandASAP"]
