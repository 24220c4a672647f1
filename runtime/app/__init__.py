"""The application layer: command line and plots (the engine never imports it)."""
