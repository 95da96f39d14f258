# START is never cleared by arming: one set arms every following frame.
# Caught by: P_noset, P_inside
s/start <= loaded | (start & ~arm);/start <= loaded | start;/
