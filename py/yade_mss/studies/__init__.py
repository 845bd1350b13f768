"""Studies: simulations of the grains, the layer above yade and specimens. The triaxial test in YADE
(:func:`triaxial`), its analysis from the records alone (numpy: :func:`derived`), and the sphere-count study
that tests the same specimen at several counts side by side (:func:`triaxialStudy`, ``mss triaxial``).
"""

from ._analysis import COLUMNS, QUASI_STATIC_I, QUASI_STATIC_UNBALANCED, derived, dilatancy, mobilized
from ._inputs import Grain, resolve as resolveInputs
from ._report import needed, verdict
from ._study import SUMMARY, TEST_DEFAULTS, estimate, triaxialStudy
from ._triaxial import TriaxialResult, clearance, placements, triaxial

__all__ = ['COLUMNS', 'QUASI_STATIC_I', 'QUASI_STATIC_UNBALANCED', 'derived', 'dilatancy', 'mobilized', 'Grain',
           'resolveInputs', 'needed', 'verdict', 'SUMMARY', 'TEST_DEFAULTS', 'estimate', 'triaxialStudy',
           'TriaxialResult', 'clearance', 'placements', 'triaxial']
