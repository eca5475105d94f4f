"""Messages over a socket between a process and the child it forked: each one its length (8 bytes)
and its bytes, so that the reader takes exactly one message however the socket splits it."""

from __future__ import annotations

import socket


def send_message(sock: socket.socket, message: bytes) -> None:
    """``message`` as one message (:func:`receive_message` reads it)."""
    sock.sendall(len(message).to_bytes(8, "little") + message)


def receive_message(sock: socket.socket) -> bytes:
    """One message of :func:`send_message`: exactly its bytes (EOFError when the other side is
    gone)."""
    size = int.from_bytes(_exactly(sock, 8), "little")
    return _exactly(sock, size)


def _exactly(sock: socket.socket, size: int) -> bytes:
    chunks, left = [], size
    while left:
        chunk = sock.recv(min(left, 1 << 20))
        if not chunk:
            raise EOFError("the other side closed the socket")
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)
