# Off by one in the set check: xmax = WIDTH is accepted (and truncated to CBITS bits).
# (coord_error stays low for the invalid set, which is armed)
# Caught by: P_invalid_error, P_invalid
s/x_ok <= ordered & ({16'd0, this_value} < WIDTH);/x_ok <= ordered \& ({16'd0, this_value} <= WIDTH);/
