"""Membrane constitutive laws (MODEL.md, "Membrane"), in UFL and in closed form.

Invariants of the surface left Cauchy-Green tensor Bs (eigenvalues lambda1^2,
lambda2^2 and 0, the zero one along the normal):

    Is  = tr(Bs) - 2                      = lambda1^2 + lambda2^2 - 2
    IIs = (tr(Bs)^2 - tr(Bs Bs)) / 2 - 1  = lambda1^2 lambda2^2 - 1
    J   = sqrt(IIs + 1)                   = lambda1 lambda2   (area ratio)

In-plane Cauchy tension (force per unit deformed length):

    tau_s = (2/J) [ dWs/dIs Bs + J^2 dWs/dIIs P ]

Laws (Es is the seed's modulus):

    neo-Hookean  Ws = Es/6 (Is + 1/(IIs+1) - 1)
                 dWs/dIs = Es/6,  dWs/dIIs = -Es/(6 J^4)   =>  tau = Es/(3J)(Bs - P/J^2)
    Skalak       Ws = Es/6 ((Is+1)^2 + alpha IIs^2 - 2 IIs - 1)
                 dWs/dIs = Es/3 (Is+1),  dWs/dIIs = Es/3 (alpha IIs - 1)

Moduli: neo-Hookean Es = 3 Gs; Skalak Es/6 = Gs/4 (Es = 3 Gs / 2), alpha = C.
"""
from __future__ import annotations

import numpy as np
import ufl

LAWS = ("neo-hookean", "skalak")


def invariants(Bs):
    trB = ufl.tr(Bs)
    Is = trB - 2
    IIs = (trB ** 2 - ufl.tr(Bs * Bs)) / 2 - 1
    return Is, IIs, ufl.sqrt(IIs + 1)


def energy_and_derivatives(law, Is, IIs, Es, alpha=1.0):
    """Ws, dWs/dIs, dWs/dIIs (works on UFL expressions and numpy arrays alike)."""
    if law == "neo-hookean":
        return Es / 6 * (Is + 1 / (IIs + 1) - 1), Es / 6 + 0 * Is, -Es / (6 * (IIs + 1) ** 2)
    if law == "skalak":
        W = Es / 6 * ((Is + 1) ** 2 + alpha * IIs ** 2 - 2 * IIs - 1)
        return W, Es / 3 * (Is + 1), Es / 3 * (alpha * IIs - 1)
    raise ValueError(f"unknown law {law!r}; known {LAWS}")


def tension(law, Bs, P, Es, alpha=1.0):
    """UFL: (tau_s, Ws, J) from Bs and the deformed projector P."""
    Is, IIs, J = invariants(Bs)
    W, W1, W2 = energy_and_derivatives(law, Is, IIs, Es, alpha)
    return (2 / J) * (W1 * Bs + J ** 2 * W2 * P), W, J


# ---------------------------------------------------------------- closed forms (numpy)
def principal_tensions(law, l1, l2, Es, alpha=1.0):
    """(T1, T2) for principal stretches (l1, l2): tau = (2/J)(W1 l_i^2 + J^2 W2)."""
    l1, l2 = np.asarray(l1, float), np.asarray(l2, float)
    Is, IIs = l1 ** 2 + l2 ** 2 - 2, (l1 * l2) ** 2 - 1
    J = l1 * l2
    _, W1, W2 = energy_and_derivatives(law, Is, IIs, Es, alpha)
    return 2 / J * (W1 * l1 ** 2 + J ** 2 * W2), 2 / J * (W1 * l2 ** 2 + J ** 2 * W2)


def energy_density(law, l1, l2, Es, alpha=1.0):
    Is, IIs = l1 ** 2 + l2 ** 2 - 2, (l1 * l2) ** 2 - 1
    return energy_and_derivatives(law, Is, IIs, Es, alpha)[0]


def isotropic_tension(law, lam, Es, alpha=1.0):
    """Uniform stretch lam (Bs = lam^2 P, J = lam^2):
    neo-Hookean T = Es/3 (1 - lam^-6);  Skalak T = 2Es/3 (lam^2 - 1 + alpha lam^2 (lam^4 - 1))."""
    if law == "neo-hookean":
        return Es / 3 * (1 - lam ** -6)
    return 2 * Es / 3 * (lam ** 2 - 1 + alpha * lam ** 2 * (lam ** 4 - 1))


def uniaxial_closed_form(law, l1, Gs, C=1.0):
    """MODEL.md "Constitutive checks": (lambda2, T1) with T2 = 0, in terms of Gs."""
    l1 = np.asarray(l1, float)
    if law == "neo-hookean":
        return l1 ** -0.5, Gs * (l1 ** 3 - 1) / l1 ** 1.5
    l2 = np.sqrt((1 + C * l1 ** 2) / (1 + C * l1 ** 4))
    J = l1 * l2
    return l2, Gs / J * (l1 ** 2 * (l1 ** 2 - 1) + C * J ** 2 * (J ** 2 - 1))


def Es_from_Gs(law, Gs):
    """neo-Hookean Es = 3 Gs;  Skalak (seed form) Es/6 = Gs/4."""
    return 3.0 * Gs if law == "neo-hookean" else 1.5 * Gs
