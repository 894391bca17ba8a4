"""Every public name (``motionsig_cli._PUBLIC``) has a docstring with an example, and the example runs.

The examples are the API page's (docs/api.md renders the docstrings), so a failing example here is a wrong
page there. Each is run with :mod:`doctest` in a fresh namespace (it imports what it uses), with
``ELLIPSIS`` and ``NORMALIZE_WHITESPACE``.
"""

from __future__ import annotations

import doctest

import pytest

import motionsig_cli

NAMES = sorted(motionsig_cli._PUBLIC)
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _own_tests(name: str) -> list[doctest.DocTest]:
    """The doctests of the public name's own docstring (a class's methods' examples are not required)."""
    obj = getattr(motionsig_cli, name)
    finder = doctest.DocTestFinder(recurse=False)
    return [t for t in finder.find(obj, name, globs={}) if t.examples]


@pytest.mark.parametrize("name", NAMES)
def test_public_name_has_a_runnable_example(name: str) -> None:
    tests = _own_tests(name)
    assert tests, f"{name}: its docstring has no example (>>>)"
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    for t in tests:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} example lines failed"


def test_the_check_fails_on_a_name_without_an_example() -> None:
    # the finder sees an example only where there is one (the check is not vacuous)
    def documented() -> None:
        """Do nothing.

        >>> 1 + 1
        2
        """

    def bare() -> None:
        """Do nothing."""

    finder = doctest.DocTestFinder(recurse=False)
    assert [t for t in finder.find(documented, "documented", globs={}) if t.examples]
    assert not [t for t in finder.find(bare, "bare", globs={}) if t.examples]
