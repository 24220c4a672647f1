"""Kernel rows, contact forces (LCP) and impulses."""
