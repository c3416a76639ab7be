"""What a crank motor must do on the floor: its torque between the exchanges, and the exchanges' impulses.

The floor drives the cranks at a prescribed speed (a velocity constraint). When a foot lands or
its contact changes (stick, slide, lift-off), the rigid contact passes an impulse through the
crank in one time step, and the motor's "torque" in that step is the impulse over the step: a
spike that doubles when the step halves. It is not a torque a motor must make, so it is reported
for what it is:

- **Between the exchanges**: every sample farther than :data:`EXCHANGE_WINDOW` from a contact
  event (a foot's mode changing, a point touching down) and past the crank ramp gives the drive
  torque's peak and RMS, and the mechanical power's peak and mean (both cranks' positive power: a
  spike's positive half over one step is the part of an exchange that depends on the step). The peaks are each crank's
  :data:`PEAK_PERCENTILE` th percentile over that time (the larger crank's): the level the drive
  passes 1 % of the time. The plain largest sample is kept too (``torque_max_Nm``), but it is not
  a figure to size by: it sits where an exchange window cuts the torque, and the drive's settling
  after a landing, right there, is the part that depends on the step most (the recommended
  walker's moves 6 % when the step halves, its 99th percentile 0.1 %). Peak, RMS and peak power
  converge as the step shrinks (a test halves it).
- **At the exchanges**: a step whose |torque| passes :data:`IMPULSE_FACTOR` times the drive's peak
  is impulsive (a heel or toe slapping down), and impulsive steps closer than :data:`IMPULSE_GAP`
  form one impact. An impact's impulse is the integral of the motor's torque over its steps less
  the straight line between the torques just before and just after [N.m.s]: the part that stays
  when the step shrinks, while a bounded torque's share over the same steps goes to zero. The
  impacts are counted from a quarter crank turn after the ramp, before the first support transfer
  (half a turn in), so the settling start's rocking is left out. An impulse under
  ``IMPULSE_FACTOR x peak x step`` cannot be told from the drive at that step: the figure says so
  (``impulse_floor_Nms``). The largest impulse converges as the step shrinks, from above (a slow
  test takes three steps). Integrating each exchange window instead does not converge: it sums
  the double support's sliding plateaus, whose lengths flicker with the step. A real drive with reflected
  inertia J on the crank shaft (rotor and gearbox) cannot deliver an impulse at once: the crank's
  speed dips by about impulse / J.

:meth:`MotorLoad.operating_point` gives the torque and speed on the motor's side of a gearbox.

Units: SI (N.m, N.m.s, W, rad/s, kg.m^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pasibot_pin.dynamics.floor.run import FloorResult
from pasibot_pin.errors import ParameterError

EXCHANGE_WINDOW: float = 0.005
"""Samples this close to a contact event belong to the exchange [s]."""

PEAK_PERCENTILE: float = 99.0
"""The drive's peak torque and power: this percentile of each crank's samples between the exchanges [%]."""

IMPULSE_FACTOR: float = 2.0
"""A step is impulsive when a crank's |torque| passes this multiple of the drive's peak [-]."""

IMPULSE_GAP: float = 0.002
"""Impulsive steps closer than this are one impact [s]."""

REFLECTED_INERTIA: float = 0.1
"""The stated reflected inertia on the crank shaft, for the speed dip [kg.m^2]: a 1e-5 kg.m^2 rotor
behind a 100:1 gearbox."""


@dataclass(frozen=True)
class MotorLoad:
    """A walk's crank-motor figures (see the module docstring).

    Attributes:
        omega: crank speed [rad/s].
        torque_peak_Nm: the :data:`PEAK_PERCENTILE` th percentile of |motor torque| between the exchanges,
            the larger crank's [N.m].
        torque_rms_Nm: its root mean square between the exchanges [N.m].
        power_peak_W: the :data:`PEAK_PERCENTILE` th percentile of one motor's mechanical power between the
            exchanges, the larger crank's [W].
        power_mean_W: both motors' mean positive power between the exchanges [W] (the verdict's energy per
            metre and cost of transport count the exchanges too, over whole strides).
        exchange_impulse_Nms: largest |impulse| of one motor in one impact (0: none above
            ``impulse_floor_Nms``) [N.m.s].
        reflected_inertia: the inertia the speed dip is stated for [kg.m^2].
        exchange_share: the share of the samples past the ramp inside an exchange window [-].
        torque_max_Nm: the largest |motor torque| between the exchanges (not step-converged) [N.m].
        impulse_floor_Nms: the smallest impulse the run's step resolves, :data:`IMPULSE_FACTOR` x the
            drive's peak x the step [N.m.s].

    """

    omega: float
    torque_peak_Nm: float
    torque_rms_Nm: float
    power_peak_W: float
    power_mean_W: float
    exchange_impulse_Nms: float
    reflected_inertia: float = REFLECTED_INERTIA
    exchange_share: float = math.nan
    torque_max_Nm: float = math.nan
    impulse_floor_Nms: float = math.nan

    @property
    def speed_dip_rad_s(self) -> float:
        """The crank speed's dip at the largest exchange with :attr:`reflected_inertia` [rad/s]."""
        return self.exchange_impulse_Nms / self.reflected_inertia

    def operating_point(self, ratio: float, efficiency: float = 0.9) -> tuple[float, float, float]:
        """The motor's side of a gearbox: (peak torque [N.m], RMS torque [N.m], speed [rad/s]).

        Raises:
            ParameterError: a ratio not above 0, or an efficiency outside (0, 1].

        """
        if not (math.isfinite(ratio) and ratio > 0):
            raise ParameterError(f"parameter 'ratio' must be > 0, got {ratio!r}")
        if not (0 < efficiency <= 1):
            raise ParameterError(f"parameter 'efficiency' must be in (0, 1], got {efficiency!r}")
        scale = 1.0 / (ratio * efficiency)
        return self.torque_peak_Nm * scale, self.torque_rms_Nm * scale, self.omega * ratio

    def summary(self) -> str:
        """Two lines: the drive between the exchanges, then the exchanges (no NaN: a figure not there is said)."""
        if not math.isfinite(self.exchange_impulse_Nms):
            return f"motor: no figures (the run ended before the cranks, ramping up, reached {self.omega:g} rad/s)"
        if not math.isfinite(self.torque_peak_Nm):
            return f"motor: no sample between the foot exchanges to size the drive by\n{self._exchanges()}"
        power = self.power_mean_W
        mean = f"mean positive power {power:.1f} W (both cranks) " if math.isfinite(power) else ""
        return (
            f"motor: peak torque {self.torque_peak_Nm:.1f} N.m, RMS {self.torque_rms_Nm:.1f} N.m, peak power "
            f"{self.power_peak_W:.0f} W, {mean}at {self.omega:g} rad/s (between the foot exchanges; peaks: "
            f"{PEAK_PERCENTILE:g}th percentiles, largest sample {self.torque_max_Nm:.1f} N.m)\n"
            f"{self._exchanges()}"
        )

    def _exchanges(self) -> str:
        """The exchanges' line: the largest impulse and its dip, or that none is resolved."""
        floor = f"{self.impulse_floor_Nms:.3f} N.m.s" if math.isfinite(self.impulse_floor_Nms) else "the step's floor"
        if not self.exchange_impulse_Nms > 0:
            return f"exchanges: no impulse through a crank above {floor} (what this time step resolves)"
        return (
            f"exchanges: impulse up to {self.exchange_impulse_Nms:.3f} N.m.s per crank, a {self.speed_dip_rad_s:.2f} "
            f"rad/s dip of the crank with {self.reflected_inertia:g} kg.m^2 reflected on its shaft (impulses under "
            f"{floor} are not resolved at this time step)"
        )


def exchange_mask(result: FloorResult, window: float = EXCHANGE_WINDOW) -> np.ndarray:
    """Samples within ``window`` [s] of a contact event: a foot's mode changing or a point touching down."""
    t = np.asarray(result.t, dtype=float)
    events: list[float] = []
    for modes in result.modes.values():
        m = np.asarray(modes)
        events.extend(t[np.flatnonzero(m[1:] != m[:-1]) + 1])
    events.extend(time for time, _side, _point in result.touchdowns)
    mask = np.zeros(len(t), dtype=bool)
    if not events:
        return mask
    events_sorted = np.sort(np.asarray(events))
    k = np.clip(np.searchsorted(events_sorted, t), 1, len(events_sorted) - 1) if len(events_sorted) > 1 else None
    if k is None:
        return np.abs(t - events_sorted[0]) <= window
    nearest = np.minimum(np.abs(t - events_sorted[k - 1]), np.abs(t - events_sorted[k]))
    return nearest <= window


def motor_load(
    result: FloorResult, omega: float, ramp: float = 0.0, reflected_inertia: float = REFLECTED_INERTIA
) -> MotorLoad:
    """The crank motors' figures of one floor run (see the module docstring).

    Args:
        result: the floor run (its ``motor_torque``, ``modes`` and ``touchdowns``).
        omega: the crank speed [rad/s].
        ramp: the crank ramp's length [s]; the samples before it are left out.
        reflected_inertia: the inertia the speed dip is stated for [kg.m^2].

    Raises:
        ParameterError: a reflected inertia not above 0.

    """
    if not (math.isfinite(reflected_inertia) and reflected_inertia > 0):
        raise ParameterError(f"parameter 'reflected_inertia' must be > 0 kg.m^2, got {reflected_inertia!r}")
    t = np.asarray(result.t, dtype=float)
    tau = np.asarray(result.motor_torque, dtype=float).reshape(len(t), -1)
    nan = math.nan
    past = t > ramp
    if len(t) < 3 or not past.any():
        return MotorLoad(omega, nan, nan, nan, nan, nan, reflected_inertia)
    exchange = exchange_mask(result)
    calm = past & ~exchange
    power = tau * omega
    if not calm.any():
        peak = rms = peak_power = largest = mean_power = nan
    else:
        mean_power = float(np.mean(np.clip(power[calm], 0.0, None).sum(axis=1)))
        peak = float(np.max(np.percentile(np.abs(tau[calm]), PEAK_PERCENTILE, axis=0)))
        rms = float(np.sqrt(np.mean(tau[calm] ** 2)))
        peak_power = float(np.max(np.percentile(power[calm], PEAK_PERCENTILE, axis=0)))
        largest = float(np.max(np.abs(tau[calm])))
    level = peak if math.isfinite(peak) else float(np.max(np.percentile(np.abs(tau[past]), PEAK_PERCENTILE, axis=0)))
    first = ramp + 0.5 * math.pi / omega if omega > 0 else ramp
    impulses = impact_impulses(t, tau, IMPULSE_FACTOR * level, t >= first)
    h = float(np.median(np.diff(t)))
    return MotorLoad(
        omega, peak, rms, peak_power, mean_power, float(max(impulses, default=0.0)), reflected_inertia,
        float(np.mean(exchange[past])), largest, IMPULSE_FACTOR * level * h,
    )  # fmt: skip


def impact_impulses(t: np.ndarray, tau: np.ndarray, threshold: float, counted: np.ndarray) -> list[float]:
    """Each impact's largest |impulse| over the motors [N.m.s] (see the module docstring).

    Args:
        t: sample times [s].
        tau: motor torques (n, motors) [N.m], each the step's impulse over the step ending at its time.
        threshold: a step is impulsive when a motor's |torque| passes it [N.m].
        counted: the samples whose impacts count.

    """
    index = np.flatnonzero(counted & (np.max(np.abs(tau), axis=1) > threshold))
    if not len(index):
        return []
    h = np.diff(t, prepend=t[0])
    gap = max(IMPULSE_GAP, 1.5 * float(np.max(h)))
    impulses = []
    for impact in np.split(index, np.flatnonzero(np.diff(t[index]) > gap) + 1):
        steps = np.arange(impact[0], impact[-1] + 1)
        a, b = max(int(steps[0]) - 1, 0), min(int(steps[-1]) + 1, len(t) - 1)
        best = 0.0
        for m in range(tau.shape[1]):
            base = np.interp(t[steps], [t[a], t[b]], [tau[a, m], tau[b, m]]) if b > a else tau[a, m]
            best = max(best, abs(float(np.sum((tau[steps, m] - base) * h[steps]))))
        impulses.append(best)
    return impulses
