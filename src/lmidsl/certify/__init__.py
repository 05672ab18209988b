"""Certification of a filter by evidence independent of the synthesis LMIs.

One concern per module:

* :mod:`.synthesis`   the synthesis LMIs re-evaluated in numpy at the solver's point;
* :mod:`.analysis`    the theorem's analysis counterpart solved with the filter fixed;
* :mod:`.system`, :mod:`.figures`  the error system as a linear system with multiplicative
  noise and its exact mean-square figures (no LMI);
* :mod:`.montecarlo`  simulation of the original model with the filter;
* :mod:`.declaration` how a theorem file declares its error system;
"""
import importlib as _importlib

#: the public names, by the module that defines them: imported when first used (PEP 562), so that
#: a theorem whose declared evidence lives in one module (``certify.indexed_evidence``,
#: ``certify.rate_bounded``) loads that module alone, not the analysis stack (scipy, the solver)
_LAZY = {"AnalysisCertificate": "analysis", "analysis_inputs": "analysis", "certify_by_analysis": "analysis",
         "ErrorSystem": "declaration", "StochasticSystem": "system",
         **{name: "figures" for name in ("Figure", "energy_to_peak", "h_infinity", "lti_hinf_norm",
                                         "ENERGY_TO_PEAK", "H_INFINITY")}}

__all__ = list(_LAZY)


def __getattr__(name):
    if name in _LAZY:
        value = getattr(_importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
