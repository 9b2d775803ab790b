"""The ETCS braking model of a train: confidence levels, failure states, and Kdry_rst from the
distribution of the deceleration ratio over failure states and tolerances (docs/etcs.md)."""

from railbrake.etcs.confidence import EBCL, K_MAX, K_STEP, coded, ebcl
from railbrake.etcs.mixture import State, k_dry, mixture_cdf, quantile
from railbrake.etcs.states import LostUnits, equal_units

__all__ = ["EBCL", "K_MAX", "K_STEP", "LostUnits", "State", "coded", "ebcl", "equal_units", "k_dry",
           "mixture_cdf", "quantile"]
