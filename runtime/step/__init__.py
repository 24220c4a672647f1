"""The time step: classification, impacts, events, integration, guards."""
