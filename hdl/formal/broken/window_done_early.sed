# window_done one clock early: on the clock of the corner pixel's strobe, not the one after.
# Caught by: P_window_done
s/assign window_done = wdone;/assign window_done = wlast;/
