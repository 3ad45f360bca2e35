"""`--scheduler` and `--timeout` of study and envelope against hostile peers, on 127.0.0.1 only.

Each peer is a thread of this test: one that accepts and never answers, one that answers
as a web server. Every connection is bounded by a short `--timeout`, every call by a
thread join, every peer by its own socket timeout and a stop event; nothing here leaves
this machine. Oracle for the peer that is a scheduler: a Dask LocalCluster's own.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator
from contextlib import contextmanager

import pytest

from hdselect.base.errors import InputError
from hdselect.base.scheduler import probe, scheduler_address, timeout_seconds
from hdselect.cli.main import main
from helpers.options import PLANAR2, one_line_error
from helpers.studies import small_study, workspace

ENVELOPE = ("envelope", str(PLANAR2), "--velocity", "180", "--acceleration", "900",
            "--starts", "64", "--moves", "2")
LIMIT = 60.0
"""The longest a call here may take before the test fails instead of hanging [s]."""


@contextmanager
def peer(answer: bytes | None, hang_up: bool = False) -> Iterator[str]:
    """A server on 127.0.0.1 that accepts and sends `answer` (None: nothing), then holds on.

    With `hang_up` it closes each connection once the answer is sent.

    Yields its address ``tcp://127.0.0.1:PORT``; stops when the block ends.
    """
    server = socket.create_server(("127.0.0.1", 0))
    server.settimeout(0.1)
    stop = threading.Event()
    held: list[socket.socket] = []

    def serve() -> None:
        while not stop.is_set():
            try:
                connection, _ = server.accept()
            except TimeoutError:
                continue
            held.append(connection)
            if answer is not None:
                connection.sendall(answer)
            if hang_up:
                connection.close()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:
        stop.set()
        thread.join(5.0)
        for connection in held:
            connection.close()
        server.close()


def bounded(capsys, *argv: str) -> tuple[int, str, str]:
    """``main(argv)`` in a thread that must end within `LIMIT`: status, stdout, stderr."""
    status: list[int] = []
    thread = threading.Thread(target=lambda: status.append(main(list(argv))), daemon=True)
    thread.start()
    thread.join(LIMIT)
    assert not thread.is_alive(), f"{argv} still running after {LIMIT} s"
    out, err = capsys.readouterr()
    return status[0], out, err


@pytest.fixture(scope="module")
def study_file(tmp_path_factory):
    return small_study(workspace(tmp_path_factory.mktemp("study")))


def _study(study_file, tmp_path, *options: str) -> tuple[str, ...]:
    return ("study", str(study_file), "--out", str(tmp_path / "s.csv"), "--workers", "1",
            *options)


@pytest.mark.parametrize("address", [
    "tcp://", "tcp://localhost:notaport", "tcp://localhost", "tcp://localhost:0",
    "tcp://localhost:65536", "udp://localhost:8786", "localhost:8786", "tcp://:8786",
    "tcp://localhost:8786/path", "tcp://user@localhost:8786", "tcp://localhost:-1", " local",
    "tcp://" + "a" * 64 + ":8786"])  # a label of 64: idna UnicodeError, exit 70, before
def test_a_bad_address_is_refused_in_one_line_before_any_work(capsys, tmp_path, study_file,
                                                              address):
    for argv in (_study(study_file, tmp_path, "--scheduler", address),
                 (*ENVELOPE, "--json", str(tmp_path / "e.json"), "--scheduler", address)):
        status, out, err = bounded(capsys, *argv)
        assert status == 2 and out == ""
        one_line_error(err, "--scheduler", "tcp://HOST:PORT", "port 1 to 65535", repr(address))
    assert list(tmp_path.iterdir()) == []


def test_addresses_that_are_well_formed_pass():
    for address in ("local", "tcp://127.0.0.1:8786", "tls://dask.example.org:1",
                    "tcp://[::1]:65535"):
        assert scheduler_address(address, "--scheduler") == address


@pytest.mark.slow
def test_a_peer_that_never_answers_ends_within_the_timeout(capsys, tmp_path, study_file):
    with peer(None) as address:
        for argv in (_study(study_file, tmp_path, "--scheduler", address, "--timeout", "0.5"),
                     (*ENVELOPE, "--json", str(tmp_path / "e.json"), "--scheduler", address,
                      "--timeout", "0.5")):
            status, out, err = bounded(capsys, *argv)
            assert status == 2 and out == ""
            one_line_error(err, "--scheduler", f"at {address} did not answer within 0.5 s")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_a_web_server_is_not_a_dask_scheduler(capsys, tmp_path, study_file):
    """Dask itself would read ``HTTP/1.1`` as a frame of 3.5e18 bytes: out of memory."""
    with peer(b"HTTP/1.1 200 OK\r\nContent-Length: 0\r\n\r\n") as address:
        for argv in (_study(study_file, tmp_path, "--scheduler", address, "--timeout", "5"),
                     (*ENVELOPE, "--scheduler", address, "--timeout", "5")):
            status, out, err = bounded(capsys, *argv)
            assert status == 2 and out == ""
            one_line_error(err, "--scheduler", f"{address} is not a Dask scheduler",
                           "(it answered b'HTTP/1.1')")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize("answer", [b"", b"\x00" * 8, b"\x10" + b"\x00" * 7 + b"x" * 16])
def test_a_peer_that_hangs_up_or_sends_no_greeting_is_refused(answer):
    with peer(answer) as address, pytest.raises(InputError) as info:
        probe(address, 0.5, "--scheduler")
    assert info.value.field == "--scheduler"


@pytest.mark.parametrize("answer", [b"", b"\x10\x00"])
def test_a_peer_that_closes_before_eight_bytes_is_refused_not_a_crash(answer):
    # found by the hostile battery: struct.error (exit 70) on a peer that hangs up
    with peer(answer, hang_up=True) as address, pytest.raises(InputError) as info:
        probe(address, 0.5, "--scheduler")
    assert info.value.field == "--scheduler"
    assert "is not a Dask scheduler" in str(info.value)


def test_nothing_listening_is_named(capsys, tmp_path, study_file):
    with socket.create_server(("127.0.0.1", 0)) as taken:
        address = f"tcp://127.0.0.1:{taken.getsockname()[1]}"
    status, _, err = bounded(capsys, *_study(study_file, tmp_path, "--scheduler", address))
    assert status == 2
    one_line_error(err, "--scheduler", f"cannot reach the Dask scheduler at {address}")


def test_a_dask_scheduler_answers_the_probe():
    distributed = pytest.importorskip("distributed")
    import logging

    with distributed.LocalCluster(n_workers=0, host="127.0.0.1", dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster:
        probe(cluster.scheduler_address, 10.0, "--scheduler")


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "1e9"])
def test_a_bad_timeout_is_refused(capsys, tmp_path, study_file, value):
    for argv in (_study(study_file, tmp_path, "--scheduler", "local", "--timeout", value),
                 (*ENVELOPE, "--scheduler", "local", "--timeout", value)):
        status, out, err = bounded(capsys, *argv)
        assert status == 2 and out == ""
        one_line_error(err, "--timeout", "more than 0 and at most 86400")
    with pytest.raises(InputError, match="at most 86400"):
        timeout_seconds(True, "timeout")


def test_a_timeout_without_a_scheduler_is_refused(capsys, tmp_path, study_file):
    for argv in (_study(study_file, tmp_path, "--timeout", "5"),
                 (*ENVELOPE, "--timeout", "5")):
        status, out, err = bounded(capsys, *argv)
        assert status == 2 and out == ""
        one_line_error(err, "--timeout", "give --scheduler too")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("starts", ["1099511627776", "131072", "32", "100"])
def test_starts_beyond_the_documented_bound_are_refused(capsys, starts):
    status, out, err = bounded(capsys, *ENVELOPE[:-4], "--starts", starts)
    assert status == 2 and out == ""
    one_line_error(err, "--starts", "a power of 2 from 64 to 65,536", starts)
