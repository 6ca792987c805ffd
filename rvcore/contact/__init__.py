"""The contact laws, written once: STEP, Hertz with its damper, friction, penetrations; the inner ring's pose."""
