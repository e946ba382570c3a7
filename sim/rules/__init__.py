"""Growth rules and the pane: where walkers freeze and where water lands."""
