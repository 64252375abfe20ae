"""swarmproof.reference_impl (see DESIGN.md section 1)."""
