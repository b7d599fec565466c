"""Crane files: one TOML file per crane, the single source of its parameters (see crane.py)."""
