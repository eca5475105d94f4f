"""The preview's HTTP corners: non-ASCII file names (RFC 5987), HEAD, clients that hang up."""

from __future__ import annotations

import http.client
import threading
from urllib.parse import unquote

import pytest

from crankdyn.preview.server import Preview, PreviewServer, content_disposition


@pytest.mark.parametrize(
    "name", ["report.pdf", "Сцена двигуна.pdf", 'a"b\\c.pdf', "ДВЗ №1 – варіант 7.pdf"]
)
def test_content_disposition_is_latin1_and_carries_the_utf8_name(name):
    header = content_disposition(name)
    header.encode("latin-1")  # what http.server does with every header: a Cyrillic name must pass
    plain = header.split('filename="', 1)[1].split('"', 1)[0]
    assert plain.isascii() and '"' not in plain and "\\" not in plain and len(plain) == len(name)
    if name.isascii() and plain == name:
        assert "filename*" not in header
    else:
        encoded = header.split("filename*=UTF-8''", 1)[1]
        assert (
            unquote(encoded, encoding="utf-8") == name and encoded.isascii() and " " not in encoded
        )


@pytest.fixture
def idle_server(tmp_path):
    """A preview server that is not building anything: it answers with its starting page."""
    scene = tmp_path / "сцена.toml"
    scene.write_text("", encoding="utf-8")
    server = PreviewServer(Preview(scene), port=0)
    thread = threading.Thread(
        target=server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True
    )
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()
        thread.join(10)


def test_head_is_answered_like_get_without_a_body(idle_server):
    port = idle_server.server_address[1]
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    connection.request("GET", "/")
    got = connection.getresponse()
    body = got.read()
    connection.request("HEAD", "/")
    head = connection.getresponse()
    assert head.status == got.status == 200
    assert head.read() == b"" and int(head.headers["Content-Length"]) == len(body) > 0
    assert head.headers["Content-Type"] == got.headers["Content-Type"]
    connection.request("HEAD", "/nowhere")
    assert connection.getresponse().status == 404
    connection.close()


@pytest.mark.parametrize("error", [BrokenPipeError, ConnectionResetError, ConnectionAbortedError])
def test_a_client_that_hangs_up_leaves_no_traceback(idle_server, capsys, error):
    try:
        raise error("the browser went away")
    except error:
        idle_server.handle_error(None, ("127.0.0.1", 1))
    assert capsys.readouterr().err == ""
    try:
        raise ValueError("a real bug")
    except ValueError:
        idle_server.handle_error(None, ("127.0.0.1", 1))
    assert "ValueError" in capsys.readouterr().err  # other errors are still reported
