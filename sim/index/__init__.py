"""Where crystals are: the hash grid, candidate cells, neighbour search and clearance."""
