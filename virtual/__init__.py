"""The virtual test: the suspended body, its instrumentation and its recordings, simulated.

The body's elastic modes come from a finite-element model of the solid
(:mod:`.elastic`, meshed by :mod:`.tetmesh`); the suspension, sensor masses and
instrumentation effects are added on top, and :mod:`.measurement` turns the
result into the FRFs a test system would record.
"""
