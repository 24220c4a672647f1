"""Scene files: reading, validation and the checks at load."""
