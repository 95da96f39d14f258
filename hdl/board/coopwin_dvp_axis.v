// coopwin_dvp_axis: a parallel (DVP) camera's frame valid, line valid and data bytes as an
// AXI4-Stream video source (AMD/Xilinx UG934: tuser[0] on a frame's first pixel, tlast on each
// line's last pixel), for window_unit_axis (thesis 2.2.2: the window logic sits between the
// camera and the window processor). Raw 8-bit mode: every byte with fval and lval is a pixel.
//
// A camera cannot wait, so this source has no tready: a beat is offered for one clock and
// must be taken then (window_unit_axis holds s_axis_tready high). A sink that stalls loses
// beats here, silently; do not put one behind this adapter without a FIFO of its own.
//
// Each pixel is held one clock, until the next clock says whether its line goes on, so that
// tlast can mark it: the stream is the camera's pixels two clocks late, one beat a byte.
// tuser goes on the first pixel after fval was seen low. After power-up, the pixels before
// the first fval low carry no tuser (window_unit_axis ignores beats before the first tuser).
`default_nettype none

module coopwin_dvp_axis (
    input  wire       clk,             // pixel clock
    input  wire       fval,            // frame valid (high through a frame)
    input  wire       lval,            // line valid (HREF)
    input  wire [7:0] data,            // the camera byte, sampled with fval and lval
    output reg  [7:0] m_axis_tdata = 8'd0,   // the pixel
    output reg        m_axis_tvalid = 1'b0,  // a beat this clock (no tready: see above)
    output reg        m_axis_tuser = 1'b0,   // the frame's first pixel
    output reg        m_axis_tlast = 1'b0    // the line's last pixel
);
    reg [7:0] held = 8'd0;             // the pixel whose line end is not known yet
    reg       held_valid = 1'b0;
    reg       held_sof = 1'b0;         // ... and it is the frame's first
    reg       sof_wait = 1'b0;         // fval was low: the next pixel starts a frame
    wire      pixel = fval & lval;

    always @(posedge clk) begin
        // The held pixel goes out now; it ended its line if no pixel follows it.
        m_axis_tvalid <= held_valid;
        m_axis_tdata <= held;
        m_axis_tuser <= held_sof;
        m_axis_tlast <= ~pixel;
        held_valid <= pixel;
        if (pixel) begin
            held <= data;
            held_sof <= sof_wait;
            sof_wait <= 1'b0;
        end
        if (~fval) sof_wait <= 1'b1;
    end
endmodule

`default_nettype wire
