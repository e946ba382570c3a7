"""How the frost looks: the surface geometry, ridges, material, maps."""
