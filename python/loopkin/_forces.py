"""The forces and the design sensitivities of a motion: the methods of
:class:`loopkin.Mechanism` that read the definition's ``bodies``,
``loads``, ``joints`` and ``sensitivities`` sections."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar, Dict, List, Tuple, Type, cast

import numpy as np

from ._values import Forces, JointReaction, MassSensitivity, Motion, Sensitivity, Values, _readonly

if TYPE_CHECKING:  # pragma: no cover
    from . import _native
    from ._model import Mechanism

__all__: List[str] = []


def _motion_args(design: Any, motion: Motion) -> Tuple[List[float], List[float], List[float]]:
    """A motion's pose and its drivers' rates and accelerations, as the
    native calls take them."""
    nd = design._nd
    return motion.q.array.tolist(), motion.qd.array[:nd].tolist(), motion.qdd.array[:nd].tolist()


class _Forces:
    """The forces and sensitivities of a design's motion (mixed into
    :class:`loopkin.Mechanism`)."""

    __slots__ = ()
    _m: "_native.Model"
    _native: ClassVar["_native.Model"]
    _nd: ClassVar[int]

    if TYPE_CHECKING:  # pragma: no cover

        @classmethod
        def driver_names(cls) -> Tuple[str, ...]: ...

    @classmethod
    def has_dynamics(cls) -> bool:
        """Whether the definition has a ``bodies`` or ``loads`` section
        (then :meth:`forces` and :meth:`Sweep.forces` compute forces)."""
        return bool(cls._native.has_dynamics())

    def forces(self, motion: Motion) -> "Forces":
        """The forces at a motion of this design (from :meth:`analyze`,
        :meth:`step` or a sweep's sample), from the definition's
        ``bodies`` and ``loads`` sections, by virtual power: each driver's
        effort Q_k = Σ_bodies [m (a_G − g) · ∂v_G/∂ḋ_k + (J α + ω × J ω) ·
        ∂ω/∂ḋ_k] − Σ_loads (F · ∂v_P/∂ḋ_k + T · ∂ω/∂ḋ_k) (a torque in N·m
        for an angle driver, a force in N for a length), the kinetic and
        potential energy, the drivers' power and the shaking force and
        moment on the frame.

        Raises:
            InvalidDynamicsError: the definition has neither section.
            SingularError: at a singular pose.
        """
        d = self._m.forces(*_motion_args(self, motion))
        return Forces(self.driver_names(), d)

    def reactions(self, motion: Motion) -> Dict[str, "JointReaction"]:
        """The force and moment each joint of the definition's ``joints``
        section carries at a motion of this design, by the Newton–Euler
        equations of every body of ``bodies`` under the ``loads``: by joint
        name, in the order declared.

        Raises:
            InvalidDynamicsError: no ``bodies``/``loads`` section, no
                joints, or joints that do not determine the reactions.
            SingularError: at a singular pose.
        """
        out = self._m.reactions(*_motion_args(self, motion))
        return {d["name"]: JointReaction(d) for d in out}

    def mass_sensitivities(self, motion: Motion) -> Dict[str, "MassSensitivity"]:
        """How each driver's effort at a motion changes with each body's
        mass and moment of inertia, by body name: the efforts are linear in
        both, so ∂Q_k/∂m = (a_G − g) · ∂v_G/∂ḋ_k and, for a planar body
        turning by an angle, ∂Q_k/∂J = α ∂ω/∂ḋ_k, exactly: what a
        counterweight's or a link's mass changes in the driving torque.

        Raises:
            InvalidDynamicsError: the definition has no ``bodies`` or
                ``loads`` section.
        """
        out = self._m.mass_sensitivities(*_motion_args(self, motion))
        drivers = self.driver_names()
        return {d["body"]: MassSensitivity(drivers, d) for d in out}

    def effort_sensitivities(self, motion: Motion) -> Dict[str, Values]:
        """How each driver's effort at a motion changes with each parameter
        of the definition's ``sensitivities`` section, the drivers' motion
        (angle, rate, acceleration) held: ∂Q_k/∂p by parameter, as
        :class:`Values` by driver. Exact: the virtual-power sum of
        :meth:`forces` differentiated by the product rule, with the
        compiler's partial derivatives of the masses, inertias, gravity,
        springs and loads. Empty without the section.

        Raises:
            InvalidDynamicsError: the definition has no ``bodies`` or
                ``loads`` section.
        """
        out = self._m.effort_sensitivities(*_motion_args(self, motion))
        drivers = self.driver_names()
        return {p: Values(drivers, _readonly(np.asarray(v))) for p, v in out.items()}

    def sensitivities(self, motion: Motion) -> Dict[str, Sensitivity]:
        """Design sensitivities of a motion of this design: for each
        parameter p of the definition's ``sensitivities`` section, ∂u/∂p
        from Φ_u ∂u/∂p = −Φ_p, and likewise the rates', accelerations' and
        points' derivatives, all exact. Empty without the section."""
        d = self._m.sensitivities(*_motion_args(self, motion))
        # A mixin: the class of a design is a compiled Mechanism.
        cls = cast("Type[Mechanism]", type(self))
        return {p: Sensitivity(cls, p, v) for p, v in d.items()}

