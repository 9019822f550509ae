"""massline: plan and evaluate the modal test that identifies mass, CoG and inertia."""

__version__ = "0.1.0"
