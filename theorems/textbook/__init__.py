"""The textbook gallery: the standard LMI results of control, each checked against python-control.

Theorem ids ``textbook.<name>``; one data convention for all of them (:mod:`.plants`).  See
``docs/gallery.md`` for the LMIs, the references and the independent checks.
"""
from .brl import THEOREMS as _BRL
from .hinf_sf import THEOREMS as _HINF_SF
from .hinf_of import THEOREMS as _HINF_OF
from .hinf_filter import THEOREMS as _HINF_FILTER
from .h2 import THEOREMS as _H2
from .kyp import THEOREMS as _KYP
from .regions import THEOREMS as _REGIONS
from .polytopic import THEOREMS as _POLYTOPIC
from .markov import THEOREMS as _MARKOV
from .fuzzy import THEOREMS as _FUZZY
from .switched import THEOREMS as _SWITCHED
from .delay import THEOREMS as _DELAY
from .h2_of import THEOREMS as _H2_OF
from .mixed import THEOREMS as _MIXED
from .hpd import THEOREMS as _HPD
from .sector import THEOREMS as _SECTOR
from .lpv import THEOREMS as _LPV

THEOREMS = [*_BRL, *_HINF_SF, *_HINF_OF, *_HINF_FILTER, *_H2, *_KYP, *_REGIONS, *_POLYTOPIC,
            *_MARKOV, *_FUZZY, *_SWITCHED, *_DELAY, *_H2_OF, *_MIXED, *_HPD, *_SECTOR, *_LPV]

__all__ = ["THEOREMS"]
