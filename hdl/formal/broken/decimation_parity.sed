# Decimation on the wrong column parity: the odd offsets (x - xmin) are delivered.
# Caught by: P_inside, P_complete
s/((xcount\[0\] == xn\[0\])/((xcount[0] != xn[0])/
