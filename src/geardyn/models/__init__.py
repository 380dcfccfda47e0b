"""Dynamic models of gear transmissions."""
