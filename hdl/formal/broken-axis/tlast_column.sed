# tlast on the window's first column instead of its last.
# Caught by: P_order, P_frames
s/wire rlast = hit \&\& (b_x == cx1);/wire rlast = hit \&\& (b_x == cx0);/
