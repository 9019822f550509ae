"""massline.identify — post-test: recordings → masslines → properties → diagnosis.

Builds on ``massline.placement`` (the rigid-body algebra lives there once).
"""
