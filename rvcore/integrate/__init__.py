"""Time integration: the loop, the methods (RK4, IMEX with its block solve and pocket check), their step sizes."""
