"""MkDocs hook: how mkdocs-jupyter executes the notebooks.

mkdocs-jupyter builds its nbconvert application from the user's nbconvert configuration (files
``jupyter_nbconvert_config.{json,py}`` on the Jupyter config path) plus its own options. This hook
puts ``docs/hooks/jupyter_config/`` first on that path (``JUPYTER_CONFIG_PATH``, for this build process
and the kernels it starts), whose ``jupyter_nbconvert_config.json`` starts every kernel with
``--IPKernelApp.matplotlib=inline``: the inline backend registers the PNG formatter for matplotlib
figures, so a cell ending in a ``matplotlib.figure.Figure`` shows the plot instead of its text repr
(``<Figure size 800x480 with 3 Axes>``), without the notebooks importing pyplot or using
``%matplotlib`` magics. The section is ``NotebookClient`` (the base class of nbconvert's
ExecutePreprocessor) because mkdocs-jupyter replaces the ``ExecutePreprocessor`` section.

The kernel's working directory is the one MkDocs runs in (the repository root).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

CONFIG_DIR = Path(__file__).resolve().parent / "jupyter_config"


def on_config(config: Any) -> Any:
    paths = [p for p in os.environ.get("JUPYTER_CONFIG_PATH", "").split(os.pathsep) if p]
    if str(CONFIG_DIR) not in paths:
        os.environ["JUPYTER_CONFIG_PATH"] = os.pathsep.join([str(CONFIG_DIR), *paths])
    return config
