"""Length-prefixed messages between a process and its child (crankdyn.parallel.messages)."""

from __future__ import annotations

import socket
import threading

import pytest

from crankdyn.parallel.messages import receive_message, send_message


def test_messages_arrive_whole_and_in_order_however_the_socket_splits_them():
    ours, theirs = socket.socketpair()
    big = bytes(range(256)) * 12_000  # 3 MB: more than one read and than the socket's buffer
    sender = threading.Thread(target=lambda: [send_message(theirs, m) for m in (big, b"", b"x")])
    sender.start()
    assert [receive_message(ours) for _ in range(3)] == [big, b"", b"x"]
    sender.join()
    theirs.close()
    with pytest.raises(EOFError):  # the other side has gone: no message, not a short one
        receive_message(ours)
    ours.close()
