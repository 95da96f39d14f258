# coord_ready falls on the clock after it rose, strobe still high: a two-phase port that
# takes the same byte again.
# (coord_ready falls while the strobe is still high)
# Caught by: P_hs_fall
s/if (~strobe_r & ready) ready <= 1'b0;/if (ready) ready <= 1'b0;/
