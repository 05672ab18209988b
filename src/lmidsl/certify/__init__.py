"""Certification of a filter by evidence independent of the synthesis LMIs.

One concern per module:

* :mod:`.synthesis`   the synthesis LMIs re-evaluated in numpy at the solver's point;
* :mod:`.analysis`    the theorem's analysis counterpart solved with the filter fixed;
* :mod:`.system`, :mod:`.figures`  the error system as a linear system with multiplicative
  noise and its exact mean-square figures (no LMI);
* :mod:`.montecarlo`  simulation of the original model with the filter;
* :mod:`.declaration` how a theorem file declares its error system;
"""
from .analysis import AnalysisCertificate, analysis_inputs, certify_by_analysis
from .declaration import ErrorSystem
from .figures import ENERGY_TO_PEAK, H_INFINITY, Figure, energy_to_peak, h_infinity, lti_hinf_norm
from .system import StochasticSystem

__all__ = ["AnalysisCertificate", "analysis_inputs", "certify_by_analysis", "ErrorSystem",
           "StochasticSystem", "Figure", "energy_to_peak", "h_infinity", "lti_hinf_norm",
           "ENERGY_TO_PEAK", "H_INFINITY"]
