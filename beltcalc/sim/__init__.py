"""Drive-train simulation: network (graph -> matrices), core (the one integrator), result."""
