"""Second-order jets: a value with its first and second time derivatives, for exact motion of a closed form.

A :class:`Jet` is (x, x', x'') of a quantity along one motion t -> theta(t). Arithmetic on jets
is the chain rule, truncated after the second derivative, so a closed form written with
``+ - * /`` and the functions below (:func:`sqrt`, :func:`cabs`, :func:`angle`, :func:`exp_i`)
gives its value, velocity and acceleration in the same pass, exactly (to round-off), with no
finite differences. The same functions take plain numbers and numpy arrays, so the closed form
is written once (:func:`pasibot_pin.model.assembly.leg_points_complex`).

Parts may be real or complex numpy arrays (complex x + i z for planar points).
"""

from __future__ import annotations

import numpy as np


class Jet:
    """(value, first derivative, second derivative) of one quantity; arrays broadcast together.

    Args:
        v: value.
        d: first time derivative.
        dd: second time derivative.

    """

    __slots__ = ("v", "d", "dd")
    __array_ufunc__ = None  # ndarray op Jet defers to Jet's reflected operators

    def __init__(self, v, d, dd):
        self.v, self.d, self.dd = v, d, dd

    # ---- arithmetic (the chain rule, to second order)
    def __add__(self, other):
        if isinstance(other, Jet):
            return Jet(self.v + other.v, self.d + other.d, self.dd + other.dd)
        return Jet(self.v + other, self.d, self.dd)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.d, -self.dd)

    def __sub__(self, other):
        if isinstance(other, Jet):
            return Jet(self.v - other.v, self.d - other.d, self.dd - other.dd)
        return Jet(self.v - other, self.d, self.dd)

    def __rsub__(self, other):
        return Jet(other - self.v, -self.d, -self.dd)

    def __mul__(self, other):
        if isinstance(other, Jet):
            return Jet(
                self.v * other.v,
                self.d * other.v + self.v * other.d,
                self.dd * other.v + 2.0 * self.d * other.d + self.v * other.dd,
            )
        return Jet(self.v * other, self.d * other, self.dd * other)

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        """1 / x: (1/x)' = -x'/x^2, (1/x)'' = 2 x'^2 / x^3 - x''/x^2."""
        r = 1.0 / self.v
        rd = -self.d * r * r
        return Jet(r, rd, (2.0 * self.d * self.d * r - self.dd) * r * r)

    def __truediv__(self, other):
        if isinstance(other, Jet):
            return self * other.reciprocal()
        return Jet(self.v / other, self.d / other, self.dd / other)

    def __rtruediv__(self, other):
        return self.reciprocal() * other

    def __getitem__(self, index) -> Jet:
        return Jet(_part(self.v, index), _part(self.d, index), _part(self.dd, index))

    @property
    def real(self) -> Jet:
        """Real part (x of a point x + i z)."""
        return Jet(np.real(self.v), np.real(self.d), np.real(self.dd))

    @property
    def imag(self) -> Jet:
        """Imaginary part (z of a point x + i z)."""
        return Jet(np.imag(self.v), np.imag(self.d), np.imag(self.dd))

    def conj(self) -> Jet:
        """Complex conjugate."""
        return Jet(np.conj(self.v), np.conj(self.d), np.conj(self.dd))


def _part(x, index):
    return x[index] if np.ndim(x) else x


def value(x):
    """The value of a jet, or ``x`` itself."""
    return x.v if isinstance(x, Jet) else x


def constant(x) -> Jet:
    """A jet that does not move."""
    return Jet(x, 0.0, 0.0)


def sqrt(x):
    """Square root: s' = x' / (2 s), s'' = (x'' - 2 s'^2) / (2 s)."""
    if not isinstance(x, Jet):
        return np.sqrt(x)
    s = np.sqrt(x.v)
    half = 0.5 / s
    sd = x.d * half
    return Jet(s, sd, (x.dd - 2.0 * sd * sd) * half)


def abs2(z):
    """|z|^2 of complex z: m' = 2 Re(conj(z) z'), m'' = 2 (|z'|^2 + Re(conj(z) z''))."""
    if not isinstance(z, Jet):
        return z.real * z.real + z.imag * z.imag
    zc = np.conj(z.v)
    return Jet(
        z.v.real * z.v.real + z.v.imag * z.v.imag,
        2.0 * (zc * z.d).real,
        2.0 * ((z.d * np.conj(z.d)).real + (zc * z.dd).real),
    )


def cabs(z):
    """|z| of complex z: m' = Re(conj(z) z') / m, m'' = (|z'|^2 + Re(conj(z) z'') - m'^2) / m."""
    if not isinstance(z, Jet):
        return np.abs(z)
    m = np.abs(z.v)
    zc = np.conj(z.v)
    md = (zc * z.d).real / m
    dd = ((z.d * np.conj(z.d)).real + (zc * z.dd).real - md * md) / m
    return Jet(m, md, dd)


def angle(z):
    """Direction arg(z) [rad]: phi' = Im(z'/z), phi'' = Im(z''/z - (z'/z)^2)."""
    if not isinstance(z, Jet):
        return np.angle(z)
    r = z.d / z.v
    return Jet(np.angle(z.v), r.imag, (z.dd / z.v - r * r).imag)


def exp_i(theta):
    """exp(i theta) of a real angle: e' = i theta' e, e'' = (i theta'' - theta'^2) e."""
    if not isinstance(theta, Jet):
        return np.exp(1j * theta)
    e = np.exp(1j * theta.v)
    return Jet(e, 1j * theta.d * e, (1j * theta.dd - theta.d * theta.d) * e)


def wrap(x):
    """The value wrapped to (-pi, pi] by atan2(sin, cos) [rad]; derivatives unchanged."""
    if not isinstance(x, Jet):
        return np.arctan2(np.sin(x), np.cos(x))
    return Jet(np.arctan2(np.sin(x.v), np.cos(x.v)), x.d, x.dd)


def where(condition, a, b):
    """``np.where`` on jets (or arrays): the parts of ``a`` where ``condition``, else of ``b``."""
    if not isinstance(a, Jet) and not isinstance(b, Jet):
        return np.where(condition, a, b)
    a = a if isinstance(a, Jet) else constant(a)
    b = b if isinstance(b, Jet) else constant(b)
    return Jet(np.where(condition, a.v, b.v), np.where(condition, a.d, b.d), np.where(condition, a.dd, b.dd))
