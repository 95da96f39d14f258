# The arming margin widened by a clock: a set completed on the clock after fval was first
# high (loaded while the frame is being armed) arms that frame with the pending registers'
# old contents, a window no set asked for this frame.
# Caught by: P_noset, P_inside
s/wire arm = fvlh & start;/wire arm = fvlh \& (start | loaded);/
