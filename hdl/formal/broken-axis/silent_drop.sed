# A beat that finds the FIFO full is dropped without being counted in OVERFLOWS: a silent loss.
# Caught by: P_conserve, P_drained
s/if (drops != 32'hFFFF_FFFF) drops <= drops + 32'd1;//
