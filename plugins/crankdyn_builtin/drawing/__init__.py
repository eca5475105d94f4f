"""Mechanism drawing stage: kinematic scheme, characteristic positions, HTML animation."""
