# A commit on the tuser beat's edge waits for the next frame (the arming margin a clock wider
# than the header states): that frame delivers the previous set, or nothing.
# Caught by: P_accounted, P_order
s/wire take = b_valid \& b_sof \& pend;/wire take = b_valid \& b_sof \& pend \& ~pend_new;/
s/reg             pdec = 1'b0, pcont = 1'b0, pend = 1'b0;/reg             pdec = 1'b0, pcont = 1'b0, pend = 1'b0, pend_new = 1'b0;/
s/wire commit = sel \& (wr_word\[2:0\] == 3'd3);/wire commit = sel \& (wr_word[2:0] == 3'd3);\n            always @(posedge aclk) pend_new <= commit \& ok;/
