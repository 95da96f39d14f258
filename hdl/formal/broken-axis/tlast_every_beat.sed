# tlast on every beat of the window, not only on the last of each row: more row ends come out
# than went in.
# Caught by: P_order
s/wire rlast = hit \&\& (b_x == cx1);/wire rlast = hit;/
