"""swarmproof.invariants (see DESIGN.md section 1)."""
