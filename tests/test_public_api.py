"""The public Python API: every name of ``motionsig_cli.__all__`` imports from the package, loads lazily,
and is documented on the API page under the module that defines it."""

import re
import subprocess
import sys
from pathlib import Path

import motionsig_cli

API_PAGE = Path(__file__).resolve().parents[1] / "docs" / "api.md"


def test_every_public_name_resolves_to_its_defining_module():
    for name, module in motionsig_cli._PUBLIC.items():
        obj = getattr(motionsig_cli, name)
        assert getattr(obj, "__module__", module) == module, name


def test_unknown_name_is_an_attribute_error():
    try:
        motionsig_cli.no_such_name  # noqa: B018
    except AttributeError as exc:
        assert "no_such_name" in str(exc)
    else:  # pragma: no cover - the test fails here
        raise AssertionError("no AttributeError")


def test_import_is_lazy():
    # the command line's start-up must not pay for numpy/scipy at `import motionsig_cli`
    code = "import sys, motionsig_cli; print('numpy' in sys.modules, 'scipy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_api_page_documents_exactly_the_public_names():
    documented = re.findall(r"^::: (\S+)$", API_PAGE.read_text(), flags=re.M)
    expected = [f"{module}.{name}" for name, module in motionsig_cli._PUBLIC.items()]
    assert sorted(documented) == sorted(expected)
