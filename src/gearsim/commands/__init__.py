"""CLI verb groups; each module defines ``register(app)``."""
