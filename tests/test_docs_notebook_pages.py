"""docs/hooks/notebook_pages.py: figure descriptions (``# alt:``) and folded cells (``# fold:``) on the notebook
pages, on HTML in the shape nbconvert's lab template renders (a code cell wrapped twice by mkdocs-jupyter, its
source in a ``pre``, its images in the output wrapper); and the convention applied in the notebooks."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import pytest
from bs4 import BeautifulSoup

from tests.docs_hooks import load_hook

ROOT = Path(__file__).resolve().parents[1]
NO_ALT = "No description has been provided for this image"


def _hook():
    return load_hook("notebook_pages")


def _cell(source: str, n_images: int) -> str:
    code = "".join(f'<span class="c1">{line}</span>\n' for line in source.splitlines())
    imgs = "".join(f'<div class="jp-RenderedImage"><img alt="{NO_ALT}" src="data:image/png;base64,AA{k}"></div>'
                   for k in range(n_images))  # fmt: skip
    return (
        '<div class="jp-Cell jp-CodeCell jp-Notebook-cell">'
        '<div class="jp-Cell jp-CodeCell jp-Notebook-cell" id="cell-id=x">'
        '<div class="jp-Cell-inputWrapper" tabindex="0"><div class="jp-InputArea jp-Cell-inputArea">'
        '<div class="jp-InputPrompt">In [1]:</div><div class="jp-CodeMirrorEditor">'
        f'<div class="highlight-ipynb hl-python"><pre><span></span>{code}</pre></div></div></div></div>'
        f'<div class="jp-Cell-outputWrapper"><div class="jp-OutputArea">{imgs}</div></div>'
        "</div></div>"
    )


PAGE = SimpleNamespace(file=SimpleNamespace(src_uri="notebooks/x.py"))


def test_descriptions_in_order_with_continuation_lines():
    src = "# alt: first figure,\n#     its second line\nfig = 1\n# alt: second figure\n#not a continuation"
    assert _hook().descriptions(src) == ["first figure, its second line", "second figure"]


def test_alt_lines_describe_the_cells_images_in_order_and_fold_wraps_the_input_only():
    hook = _hook()
    html = _cell("# fold: Setup: imports\nimport numpy", 0) + _cell("# alt: A &lt;b&gt; curve\n# alt: B\nfig", 2)
    out = BeautifulSoup(hook.on_page_content(html, PAGE, None, None), "html.parser")
    assert [img["alt"] for img in out.select("img")] == ["A <b> curve", "B"]
    details = out.select("details.nb-fold")
    assert len(details) == 1 and details[0].summary.get_text() == "Setup: imports"
    assert details[0].select_one("div.jp-Cell-inputWrapper") is not None
    assert details[0].select_one("div.jp-Cell-outputWrapper") is None


def test_an_image_without_a_description_keeps_nbconverts_text_and_extra_alt_lines_warn(caplog):
    hook = _hook()
    out = hook.on_page_content(_cell("fig", 1) + _cell("# alt: one\n# alt: two\nfig", 1), PAGE, None, None)
    assert [img["alt"] for img in BeautifulSoup(out, "html.parser").select("img")] == [NO_ALT, "one"]
    assert "2 '# alt:' line(s) for 1 image(s)" in caplog.text


def test_other_pages_are_left_alone():
    html = _cell("# alt: x\nfig", 1)
    page = SimpleNamespace(file=SimpleNamespace(src_uri="index.md"))
    assert _hook().on_page_content(html, page, None, None) == html


@pytest.mark.parametrize("path", sorted((ROOT / "notebooks").glob("*.py")), ids=lambda p: p.stem)
def test_every_notebook_figure_cell_has_a_description(path):
    """A cell that shows a figure (ends in `fig`, a `…_figure(…)` call, `display(Image(…))`) carries an
    `# alt:` line: a static check of the convention; the browser check verifies the built pages."""
    text = path.read_text(encoding="utf-8")
    cells = re.split(r"^# %%.*$", text, flags=re.M)[1:]
    markers = re.compile(r"^(fig|figs\[\d\]|\w+_figure\(.*|display\(.*(_figure|Image)\(.*)$", re.M)
    missing = [c.strip().splitlines()[0] for c in cells if markers.search(c) and "# alt:" not in c]
    assert not missing, f"{path.name}: figure cells without '# alt:': {missing}"
