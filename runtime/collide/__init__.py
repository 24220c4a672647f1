"""Broad and narrow phase: which features of which bodies are in contact."""
