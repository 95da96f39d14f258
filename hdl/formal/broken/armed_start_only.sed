# armed is START alone: it falls when the frame takes the set, while the window is still open.
# Caught by: P_armed
s/assign armed = start | strben;/assign armed = start;/
