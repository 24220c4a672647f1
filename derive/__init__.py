"""SymPy derivation of the contact equations of the note "Curved Edge Physics" (Neumann 2015)."""
