"""Bodies, shapes and scenes: the data the engine steps (no physics)."""
