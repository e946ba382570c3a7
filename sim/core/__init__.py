"""The simulation's core: `FrostSim` (the orchestrator) and the parts it runs a tick over."""
