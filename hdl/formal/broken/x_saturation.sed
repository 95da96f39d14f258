# The X counter no longer stops at COUNT_MAX: on a line longer than 2^CBITS pixels it wraps,
# and pixels past column WIDTH-1 land on window columns again.
# (a strobe for a pixel beyond column WIDTH-1)
# Caught by: P_inside, P_bounds
s/else if (pvc & (xcount != COUNT_MAX)) xcount/else if (pvc) xcount/
