"""The registry of the amplitude densities a user can name (``--density``, ATC-10 §3.6 Fig. 3.2 and
§3.7): each member (:class:`DensityKind`) says what it supports — an exact ROC, importance sampling, a
closed-form second moment, its report id and figure — so that callers ask the member instead of testing
types or names. The densities themselves are in :mod:`motionsig_cli.surveillance.amplitude` and, for the
chip-level PSK member, :mod:`motionsig_cli.surveillance.psk_amplitude`; the registry imports both, and
neither imports it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.amplitude import (
    AmplitudeDensity,
    Arcsine,
    Gaussian,
    Laplace,
    Triangular,
    TwoPoint,
    Uniform,
    _check_scale,
)
from motionsig_cli.surveillance.psk_amplitude import PSKAmplitude

__all__ = ["DENSITIES", "DensityKind", "density", "density_kind", "kind_of"]


def _psk(ref: tuple[int, ...], family: tuple[tuple[int, ...], ...] | None = None) -> AmplitudeDensity:
    return PSKAmplitude(ref, family)


@dataclass(frozen=True)
class DensityKind:
    """A member of the registry :data:`DENSITIES`: a density a user can name and what it supports.

    Attributes:
        name: The name (``--density``).
        description: What it is, in a few words.
        law: ``"atoms"`` (impulses: ``atoms()``), ``"pdf"`` (a density function: ``pdf(x)``) or
            ``"mixture"`` (neither: a quadrature mixture, known through its CGF and sampler).
        report_id: C1 … C4 of ATC-10 Fig. 3.2, or None.
        figure: The ATC-10 figure of its ROC bounds (Figs 3.3–3.6), or None.
        assumed: Its shape is our assumption (the report does not describe C₁, C₃, C₄).
        exact_roc: The sum of k draws has a closed-form tail (``log_tail``): the exact ROC exists.
        importance: A tilted sampler exists (``sample_tilted``): importance sampling works.
        closed_form_b: b is a closed form of its parameter (psk: a quadrature of the CGF).
        chip_level: Built from a reference code (``from_code``) and drawn at the chip level, not from b.
        of_b: b → the density (None for a chip-level member).
        from_code: (reference code, family codes or None) → the density (chip-level members only).
    """

    name: str
    description: str
    law: Literal["atoms", "pdf", "mixture"]
    report_id: str | None = None
    figure: str | None = None
    assumed: bool = False
    exact_roc: bool = False
    importance: bool = False
    closed_form_b: bool = True
    chip_level: bool = False
    of_b: Callable[[float], AmplitudeDensity] | None = None
    from_code: Callable[..., AmplitudeDensity] | None = None


DENSITIES: dict[str, DensityKind] = {
    k.name: k
    for k in (
        DensityKind("two-point", "C₂, ±√b with probability ½ (quasi-optimal, 3.7.1)", "atoms", "C2", "3.4",
                    exact_roc=True, importance=True, of_b=lambda b: TwoPoint(math.sqrt(b))),
        DensityKind("uniform", "C₁ (assumed), U(−√(3b), √(3b))", "pdf", "C1", "3.3", assumed=True,
                    exact_roc=True, importance=True, of_b=lambda b: Uniform(math.sqrt(3.0 * b))),
        DensityKind("triangular", "C₃ (assumed), the sum of two U(−c, c), c = √(3b/2)", "pdf", "C3", "3.5",
                    assumed=True, exact_roc=True, importance=True,
                    of_b=lambda b: Triangular(math.sqrt(1.5 * b))),
        DensityKind("gaussian", "C₄ (assumed), N(0, b)", "pdf", "C4", "3.6", assumed=True, exact_roc=True,
                    importance=True, of_b=Gaussian),
        DensityKind("laplace", "Laplace of scale √(b/2)", "pdf", exact_roc=True, importance=True,
                    of_b=lambda b: Laplace(math.sqrt(0.5 * b))),
        DensityKind("arcsine", "√(2b) cos φ, φ uniform (one constant-envelope interferer)", "pdf",
                    of_b=lambda b: Arcsine(math.sqrt(2.0 * b))),
        DensityKind("psk", "chip-level PSK signatures of a reference code (3.3.7)", "mixture",
                    closed_form_b=False, chip_level=True, from_code=_psk),
    )
}  # fmt: skip
"""The densities a user can name, in the order of the help text."""


def density_kind(name: str, field: str = "density") -> DensityKind:
    """The registry member ``name`` (a name, or a report id C1 … C4, in any case)."""
    key = str(name).lower()
    for kind in DENSITIES.values():
        if key == kind.name or (kind.report_id is not None and key == kind.report_id.lower()):
            return kind
    raise ConfigError(field, name, f"is an unknown density; use one of {', '.join(DENSITIES)} or C1…C4")


def kind_of(dens: AmplitudeDensity) -> DensityKind | None:
    """The registry member of a density (None for one a user cannot name, e.g. :class:`Discrete`)."""
    return DENSITIES.get(dens.name)


def density(name: str, b: float) -> AmplitudeDensity:
    """The density ``name`` (or a report id C1…C4) with second moment ``b``."""
    b = _check_scale("b", b)
    kind = density_kind(name)
    if kind.of_b is None:
        raise ConfigError("density", name, "is built from a reference code, not from a second moment b")
    return kind.of_b(b)
