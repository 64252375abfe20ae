"""swarmproof.checkers (see DESIGN.md section 1)."""
