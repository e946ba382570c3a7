"""Files and gestures: session logs, parameter sets, JSON and atomic writes."""
