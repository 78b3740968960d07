"""The embedded sensor simulator: applied force -> bridge voltage as an ADC would read it."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

from ..physics.chain import SensorChain
from ..physics.viscoelastic import PAPER_BURGERS, ViscoelasticModel

__all__ = ["BridgeSimulator"]


@dataclass
class BridgeSimulator:
    """A polymer force sensor with a Wheatstone bridge and an ADC.

    voltage = quantise(chain.forward(F) + noise). The truth ``chain`` defaults
    to the viscoelastic ``model`` (the paper's Burgers parameters) followed by
    a bridge offset of ``offset_v``; pass a chain to add effects (nonlinear
    gain, sensor lag, thermal drift, offset drift, ...).

    noise_std_v: white noise (V, 1 sigma); adc_bits / adc_range_v: quantiser
    (0 bits disables it); seed: noise seed. ``simulate`` can be called block
    after block: element states carry over.
    """

    model: Optional[ViscoelasticModel] = PAPER_BURGERS
    offset_v: float = 0.05
    noise_std_v: float = 1e-3
    adc_bits: int = 16
    adc_range_v: tuple[float, float] = (-5.0, 5.0)
    seed: int = 0
    chain: Optional[SensorChain] = None
    _states: list[Any] = field(init=False, repr=False)
    _rng: np.random.Generator = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.chain is None:
            if self.model is None:
                raise ValueError("a simulator needs a viscoelastic model or a chain")
            self.chain = SensorChain.from_model(self.model, offset_v=self.offset_v)
        else:
            self.model = self.chain.viscoelastic
        self.reset()

    def _truth(self) -> SensorChain:
        """The sensor truth the simulator runs (``chain``, set by the constructor)."""
        if self.chain is None:
            raise ValueError("the simulator has no chain")
        return self.chain

    def reset(self) -> None:
        """Sensor relaxed and unloaded, noise sequence restarted."""
        self._states = self._truth().forward_states()
        self._rng = np.random.default_rng(self.seed)

    @property
    def lsb_v(self) -> float:
        """One quantiser step [V] (0 without a quantiser)."""
        lo, hi = self.adc_range_v
        return (hi - lo) / (2**self.adc_bits) if self.adc_bits else 0.0

    def simulate(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike,
                 temperature_c: Optional[npt.ArrayLike] = None) -> npt.NDArray[np.float64]:
        """Bridge voltage (V) for the force samples; continues from the previous block.

        temperature_c: per-sample (or scalar) temperature for thermal elements.
        """
        v = self._truth().forward(t_s, force_n, aux={"temperature_c": temperature_c}, states=self._states)
        if self.noise_std_v:
            v = v + self._rng.normal(0.0, self.noise_std_v, size=v.shape)
        if self.adc_bits:
            lo, hi = self.adc_range_v
            v = np.clip(np.round((v - lo) / self.lsb_v) * self.lsb_v + lo, lo, hi - self.lsb_v)
        return v
