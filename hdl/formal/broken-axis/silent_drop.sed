# A beat that finds the FIFO full is dropped without being counted.
# Caught by: P_accounted
s/if (drops != 32'hFFFF_FFFF) drops <= drops + 32'd1;/drops <= drops;/
