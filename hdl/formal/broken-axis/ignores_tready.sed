# The output register reloads whether or not the sink took its beat: a beat offered and not
# taken is replaced (the AXI4-Stream rule broken, and the beat lost uncounted).
# Caught by: P_stable
s/wire load = ~empty \& (~qvalid | m_axis_tready\[k\]);/wire load = ~empty;/
