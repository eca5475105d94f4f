"""The live preview swaps the sections a save changed into the open tab (``/update``): only those
sections are rendered and sent again, and the tab's page is then the page a fresh rendering of the
saved scene gives."""

from __future__ import annotations

import json
import os
import re
import shutil
import threading

import pytest
from test_serve import BASH, CHROMIUM, DevTools, _wait

from crankdyn.cli import examples_dir
from crankdyn.preview.server import (
    BUILDER_THREAD,
    DRAWING_NICE,
    Preview,
    PreviewServer,
    page_parts,
)

STAGES = ["forces"]  # kinematics, indicator, forces: a mass changes the forces only

PAGE = (
    "<!DOCTYPE html><html><head><title>T</title></head><body>\n"
    '<section class="title-page"><p>title</p></section>\n'
    '<section class="chapter" id="sec-1"><section class="inner">a</section><p>1</p></section>\n'
    '<section class="chapter" id="sec-2"><p>2</p></section>\n'
    '<p class="colophon">made</p>\n</body></html>'
)


def test_a_page_is_parted_into_its_top_level_sections_each_with_an_id():
    parts = page_parts(PAGE)
    assert parts.ids == ("preview-title-page", "sec-1", "sec-2")
    assert parts.parts[1].endswith("<p>1</p></section>")  # the nested section stays inside
    assert parts.html == PAGE.replace(
        '<section class="title-page">', '<section id="preview-title-page" class="title-page">'
    )
    assert '<p class="colophon">made</p>' in parts.frame[-1]


def test_only_the_changed_parts_are_sent_and_a_changed_frame_reloads():
    before = page_parts(PAGE)
    after = page_parts(PAGE.replace("<p>2</p>", "<p>two</p>"))
    assert after.changed_since(before) == {
        "sec-2": '<section class="chapter" id="sec-2"><p>two</p></section>'
    }
    assert page_parts(PAGE).changed_since(before) == {}
    retitled = page_parts(PAGE.replace("<title>T</title>", "<title>U</title>"))
    assert retitled.changed_since(before) is None
    fewer = page_parts(PAGE.replace('<section class="chapter" id="sec-2"><p>2</p></section>\n', ""))
    assert fewer.changed_since(before) is None


def test_a_page_that_cannot_be_parted_is_loaded_anew():
    assert page_parts("<html><body><p>no sections</p></body></html>") is None
    unclosed = PAGE.replace("<p>1</p></section>", "<p>1</p>")  # sec-1 would hold sec-2
    assert page_parts(unclosed) is None
    twice = PAGE.replace('id="sec-2"', 'id="sec-1"')
    assert page_parts(twice) is None


def _scene(tmp_path):
    scene = tmp_path / "engine.toml"
    shutil.copy(examples_dir() / "petrol-1cyl.toml", scene)
    return scene


def _edit_rod(scene, factor: float) -> None:
    text = scene.read_text(encoding="utf-8")
    edited = re.sub(
        r'(?m)^(rod\s*=\s*")([0-9.]+)', lambda m: f"{m[1]}{float(m[2]) * factor:.5f}", text, count=1
    )
    assert edited != text
    scene.write_text(edited, encoding="utf-8")


def _as_drawn(html: str) -> str:
    """``html`` with each figure as its name (its URL's token, a blank image until it is drawn,
    left out) and the stages' measured run times blanked."""
    html = re.sub(r'src="data:image/svg\+xml,[^"]*" data-figure="([^"]*)"', r'src="\1"', html)
    html = re.sub(r' data-figure="[^"]*"', "", html)  # kept by a blank image's place once drawn
    html = re.sub(r'src="figures/[^/"]+/([^"]+)"', r'src="figures/\1"', html)
    return re.sub(
        r'(<td class="text" style="text-align:left">[^<]*</td><td>)[^<]*(</td>)', r"\1…\2", html
    )


def ids_of(snapshot, stage: str) -> int:
    """The index of ``stage``'s section among the snapshot's parts."""
    return snapshot.parts.ids.index(_stage_id(snapshot.parts, stage))


def _stage_id(parts, stage: str) -> str:
    return next(
        k for k, p in zip(parts.ids, parts.parts, strict=True) if f'data-stage="{stage}"' in p
    )


def test_a_mass_edit_sends_only_the_changed_sections_and_gives_the_fresh_page(tmp_path):
    scene = _scene(tmp_path)
    preview = Preview(scene, stages=STAGES)
    first = preview.build()
    kept = {f.name: f for f in first.figures}
    _edit_rod(scene, 1.05)
    built_before_page = []
    publish = preview._publish

    def publish_noting_built(*args):
        built_before_page.extend(f.name for f in args[4] if f._figure is not None)
        return publish(*args)

    preview._publish = publish_noting_built
    edited = preview.build()
    # the new figures of the edited section were not built before the page went out: each has
    # its last drawing's size (pt, as its SVG says) on its blank image meanwhile
    assert not [name for name in built_before_page if name.startswith("fig_4_")]
    for figure in edited.figures:
        if figure.name.startswith("fig_4_"):
            width, height = re.search(
                rb'width="([0-9.]+)pt" height="([0-9.]+)pt"', figure.svg
            ).groups()
            blank = f"width%3D%27{float(width):.0f}pt%27%20height%3D%27{float(height):.0f}pt%27"
            assert blank in edited.parts.parts[ids_of(edited, "forces")]
    # rendered again: the forces section alone; the others' figures are the drawn ones, shown
    # by their URLs at once
    assert preview.sections_cache.renders == {"kinematics": 1, "indicator": 1, "forces": 2}
    for figure in edited.figures:
        if figure.name in kept and not figure.name.startswith("fig_4_"):
            assert figure is kept[figure.name]
            assert f'src="figures/{figure.preview_token}/{figure.name}"' in edited.page.decode()
        else:
            assert figure.name.startswith("fig_4_") and figure is not kept.get(figure.name)

    update = preview.changes_after(first.version, timeout=0)
    assert update["version"] == edited.version
    sent = update["parts"]
    ids = first.parts.ids
    assert _stage_id(first.parts, "forces") in sent and _stage_id(first.parts, "input") in sent
    for unchanged in ("kinematics", "indicator"):
        assert _stage_id(first.parts, unchanged) not in sent
    # the tab's page after the swap (its parts replaced by id) is the fresh rendering's
    swapped = [sent.get(key, part) for key, part in zip(ids, first.parts.parts, strict=True)]
    fresh = Preview(scene, stages=STAGES).build()
    assert fresh.parts.ids == ids and fresh.parts.frame == edited.parts.frame
    assert [_as_drawn(p) for p in swapped] == [_as_drawn(p) for p in fresh.parts.parts]
    assert {f.name: f.svg for f in edited.figures} == {f.name: f.svg for f in fresh.figures}


def test_a_tab_too_far_behind_or_a_new_frame_is_told_to_reload(tmp_path):
    scene = _scene(tmp_path)
    preview = Preview(scene, stages=["kinematics"])
    first = preview.build()
    assert preview.changes_after(first.version, timeout=0) == {"version": first.version}
    assert preview.changes_after("unknown-1", timeout=0) == {
        "version": first.version,
        "reload": True,
    }
    text = scene.read_text(encoding="utf-8")
    scene.write_text(re.sub(r"(?m)^title = .*$", 'title = "Another"', text, count=1), "utf-8")
    retitled = preview.build()
    assert preview.changes_after(first.version, timeout=0) == {
        "version": retitled.version,
        "reload": True,
    }


# --------------------------------------------------------------------------- in the browser

# each top-level section of the tab and of a page parsed from ``fresh``, by id, as serialised
_SECTIONS = """(function(fresh){
  var parsed = new DOMParser().parseFromString(fresh, 'text/html');
  function sections(doc){ var out = {};
    Array.prototype.forEach.call(doc.body.children, function(e){
      if(e.tagName !== 'SCRIPT'){ out[e.id] = e.outerHTML; } });
    return out; }
  return [sections(document), sections(parsed)];
})(%s)"""


@pytest.mark.slow  # drives Chromium: in the slow tier, which CI runs
@pytest.mark.skipif(
    CHROMIUM is None or BASH is None,
    reason="Debian's chromium package is not installed (.ci/setup.sh installs it)",
)
@pytest.mark.long
def test_the_open_tab_swaps_in_the_changed_sections_in_place(tmp_path):
    scene = _scene(tmp_path)
    preview = Preview(scene, stages=STAGES, debounce_ms=100)
    server = PreviewServer(preview, port=0)
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.1})
    browser = None
    preview.start()
    thread.start()
    try:
        _wait(lambda: preview.snapshot.state == "report" and not preview.building, 60, "a page")
        browser = DevTools(server.url, tmp_path / "profile")
        browser.attach(server.url)
        shown = preview.snapshot
        _wait(
            lambda: (
                browser.evaluate("document.documentElement.dataset.version", tolerant=True)
                == shown.version
            ),
            30,
            "the page in the tab",
        )
        kinematics = _stage_id(shown.parts, "kinematics")
        forces = _stage_id(shown.parts, "forces")
        indicator = _stage_id(shown.parts, "indicator")
        # this page's state: a reload would wipe it, a replaced section loses its own mark
        browser.evaluate(
            f"window.__mark = 1; document.getElementById({json.dumps(kinematics)}).__mark = 1;"
            f"document.getElementById({json.dumps(forces)}).__mark = 1;"
            f"document.getElementById({json.dumps(indicator)}).scrollIntoView();"
        )
        where = f"document.getElementById({json.dumps(indicator)}).getBoundingClientRect().top"
        top = browser.evaluate(where)

        _edit_rod(scene, 0.95)
        _wait(
            lambda: not preview.building and preview.snapshot.version != shown.version,
            60,
            "the build of the save",
        )
        edited = preview.snapshot
        _wait(
            lambda: (
                browser.evaluate("document.documentElement.dataset.version", tolerant=True)
                == edited.version
            ),
            30,
            "the tab to take the new build",
        )
        assert browser.evaluate("window.__mark") == 1, "the tab reloaded instead of swapping"
        marks = browser.evaluate(
            f"[document.getElementById({json.dumps(kinematics)}).__mark,"
            f" document.getElementById({json.dumps(forces)}).__mark]"
        )
        assert marks == [1, None]  # kept as it was; replaced
        assert abs(browser.evaluate(where) - top) < 1  # where the reader was stays in view

        fresh = Preview(scene, stages=STAGES).build()
        tab, parsed = browser.evaluate(_SECTIONS % json.dumps(fresh.page.decode()))
        assert list(tab) == list(parsed) and set(fresh.parts.ids) <= set(tab)
        for key in parsed:
            assert _as_drawn(tab[key]) == _as_drawn(parsed[key]), key
    finally:
        if browser is not None:
            browser.close()
        server.shutdown()
        server.server_close()
        preview.stop()
        thread.join(10)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the drawers are forked")
def test_a_process_the_builder_forks_runs_below_the_server():
    # the figures' drawers and the study worker work behind the page the tab takes meanwhile
    def fork_and_read() -> int:
        read_end, write_end = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: its priority, then leave at once
            os.write(write_end, str(os.getpriority(os.PRIO_PROCESS, 0)).encode())
            os._exit(0)
        os.close(write_end)
        with os.fdopen(read_end) as pipe:
            told = int(pipe.read())
        os.waitpid(pid, 0)
        return told

    here = os.getpriority(os.PRIO_PROCESS, 0)
    assert fork_and_read() == here  # forked by any other thread: as this process
    found = []
    builder = threading.Thread(target=lambda: found.append(fork_and_read()), name=BUILDER_THREAD)
    builder.start()
    builder.join(30)
    assert found == [min(here + DRAWING_NICE, 19)]
