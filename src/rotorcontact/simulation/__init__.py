"""The hybrid simulator: guaranteed impact location, the compiled event loop (flights, impacts,
chatter, sliding and rolling contact), the `Trajectory` it returns and the classification of motion."""
