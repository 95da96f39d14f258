// window_unit: one windowing unit of the cooperative-windowing tracker (thesis 2.2.2,
// Figs. 2.3, A1.1, A1.2, Appendix B). A processor writes a window's coordinates over a
// byte-wide strobe/ready port; the unit counts the camera's pixels and lines and strobes
// exactly the window's pixels out, one window per coordinate set, at frame rate.
//
// The same logic as the rust-hdl blocks WindowUnit and CoordPort (hdl/src/window_unit.rs,
// hdl/src/coord_port.rs), register for register and under the same names: Yosys proves
// rust-hdl's netlist of them equivalent to this module (hdl/tests/equivalence.rs).
//
// Status: armed is high while a valid set waits for a frame or its window is open;
// window_done is high for one clock, the clock after the strobe of the window's corner pixel
// (xmax, ymax) (where it would be, when decimation skips it); set_accepted is high for one
// clock, the clock after a valid set's last byte was taken, as coord_error shows the verdict.
// Contract and timing: docs/window-logic.md.
//
// Coordinates: with WIDTH and HEIGHT <= 256 a set is 4 bytes (xmin, xmax, ymin, ymax);
// otherwise 8 bytes, each coordinate high byte first. A set is valid iff
// xmin < xmax < WIDTH and ymin < ymax < HEIGHT; an invalid set raises coord_error and is
// refused. A valid set whose last byte is taken on clock s arms the first frame whose fval is
// first sampled high on clock s+1 or later, and delivers that frame's window once; a set
// completed later waits for the next frame. Of two sets completed before a frame, the later wins.
//
// Camera: a pixel is on `pixel` on a clock with fval, lval and pixel_valid high. Lines need at
// least 2 clocks of lval low between them, and a frame at least 2 clocks of fval high before
// its first lval (the Y flags are registered). Pixels beyond column WIDTH-1 or lines beyond
// HEIGHT-1 are never delivered.
`timescale 1ns / 1ps
`default_nettype none

module window_unit #(
    parameter integer WIDTH = 256,      // pixels per line (16..4096)
    parameter integer HEIGHT = 256,     // lines per frame (16..4096)
    parameter integer PIXEL_BITS = 8    // bits per pixel (8..16)
) (
    input  wire                  clock,        // pixel clock (thesis STROBE, PVC): all logic on its rising edge
    input  wire                  fval,         // frame valid (thesis FVAL)
    input  wire                  lval,         // line valid (thesis LVAL); one pulse is one line
    input  wire [PIXEL_BITS-1:0] pixel,        // camera data (thesis OD0-OD7)
    input  wire                  coord_strobe, // coordinate byte offered (thesis CSTRB1)
    input  wire [7:0]            coord_data,   // coordinate byte (thesis port 1 D0-D7)
    output wire                  coord_ready,  // coordinate byte taken (thesis CRDY1)
    input  wire                  decimate,     // 25% resolution for the set being completed
    output wire                  pixel_strobe, // high one clock per delivered pixel (thesis CSTRB4)
    output wire [PIXEL_BITS-1:0] pixel_out,    // the delivered pixel, valid with pixel_strobe (port 4)
    output wire                  coord_error,  // the last complete set was invalid and was refused
    input  wire                  pixel_valid,  // a pixel is on `pixel` this clock (with fval & lval)
    input  wire                  reset,        // synchronous, active high: back to the power-on state
    output wire                  armed,        // a valid set waits for a frame, or its window is open
    output wire                  window_done,  // high one clock: the clock after the window's last pixel
    output wire                  set_accepted  // high one clock: a valid set was latched (coord_error low)
);
    // Counter and coordinate width: enough for the larger of WIDTH and HEIGHT.
    localparam integer LARGEST = WIDTH > HEIGHT ? WIDTH : HEIGHT;
    localparam integer CBITS = $clog2(LARGEST);
    // Two bytes per coordinate once a coordinate no longer fits one.
    localparam [0:0] WIDE = LARGEST > 256;
    localparam [2:0] LAST_BYTE = WIDE ? 3'd7 : 3'd3;   // a set's last byte: ymax (low)
    localparam [2:0] XMAX_BYTE = WIDE ? 3'd3 : 3'd1;   // the byte that completes xmax
    // The counters stop here, so a longer line or frame never wraps onto window coordinates.
    localparam [CBITS-1:0] COUNT_MAX = {CBITS{1'b1}};

    // ---------------------------------------------------------------------------------------
    // Coordinate port (Fig. A1.1): a synchronous four-phase handshake, the bytes shifted in,
    // the set checked on the clock after its last byte.
    // ---------------------------------------------------------------------------------------
    reg                 strobe_r = 1'b0;    // CSTRB1 registered on arrival
    reg           [7:0] data_r = 8'd0;      // port 1 data registered on arrival
    reg                 decimate_r = 1'b0;  // decimate registered on arrival
    reg                 ready = 1'b0;       // thesis CRDY1
    reg           [2:0] index = 3'd0;       // which byte of the set comes next
    // The thesis's shift registers, cut to the last three bytes taken: each byte enters at sh7
    // and moves one on. When the byte completing xmax (or ymax) is on data_r, the coordinate
    // pair is whole: {sh5, sh6} and {sh7, data_r} when WIDE, sh7 and data_r otherwise. The pair
    // is checked and kept then, so the check after the last byte is two flip-flops.
    reg           [7:0] sh5 = 8'd0, sh6 = 8'd0, sh7 = 8'd0;
    reg                 x_ok = 1'b0;        // xmin < xmax < WIDTH, judged as xmax arrived
    reg                 y_ok = 1'b0;        // ymin < ymax < HEIGHT, judged as ymax arrived
    reg     [CBITS-1:0] in_xn = {CBITS{1'b0}};  // the set being written: xmin
    reg     [CBITS-1:0] in_xx = {CBITS{1'b0}};  // the set being written: xmax
    reg     [CBITS-1:0] in_yn = {CBITS{1'b0}};  // the set being written: ymin
    reg     [CBITS-1:0] in_yx = {CBITS{1'b0}};  // the set being written: ymax
    reg                 in_dec = 1'b0;      // decimate sampled with the set's last byte
    reg                 check = 1'b0;       // the set's last byte arrived on the last edge
    reg     [CBITS-1:0] set_xn = {CBITS{1'b0}};  // pending window: minimum column (thesis XN)
    reg     [CBITS-1:0] set_xx = {CBITS{1'b0}};  // pending window: maximum column (thesis XX)
    reg     [CBITS-1:0] set_yn = {CBITS{1'b0}};  // pending window: minimum row (thesis YN)
    reg     [CBITS-1:0] set_yx = {CBITS{1'b0}};  // pending window: maximum row (thesis YX)
    reg                 set_dec = 1'b0;     // pending window is decimated
    reg                 error = 1'b0;       // the last complete set was refused
    reg                 accepted = 1'b0;    // a valid set was latched on the last edge

    wire take = strobe_r & ~ready;          // a byte offered and not yet taken
    // The coordinate the byte taken now completes, and the one before it.
    wire [15:0] this_value = WIDE ? {sh7, data_r} : {8'd0, data_r};
    wire [15:0] prev_value = WIDE ? {sh5, sh6} : {8'd0, sh7};
    wire ordered = prev_value < this_value;
    // A valid set is latched on this edge (the thesis's AC pulse that sets START).
    wire loaded = check & x_ok & y_ok;

    always @(posedge clock) begin
        if (reset) begin
            strobe_r <= 1'b0; data_r <= 8'd0; decimate_r <= 1'b0;
            ready <= 1'b0; index <= 3'd0; check <= 1'b0;
            sh5 <= 8'd0; sh6 <= 8'd0; sh7 <= 8'd0;
            x_ok <= 1'b0; y_ok <= 1'b0; in_dec <= 1'b0;
            in_xn <= {CBITS{1'b0}}; in_xx <= {CBITS{1'b0}};
            in_yn <= {CBITS{1'b0}}; in_yx <= {CBITS{1'b0}};
            set_xn <= {CBITS{1'b0}}; set_xx <= {CBITS{1'b0}};
            set_yn <= {CBITS{1'b0}}; set_yx <= {CBITS{1'b0}};
            set_dec <= 1'b0; error <= 1'b0; accepted <= 1'b0;
        end else begin
            strobe_r <= coord_strobe;
            data_r <= coord_data;
            decimate_r <= decimate;
            check <= take & (index == LAST_BYTE);
            if (take) begin
                ready <= 1'b1;
                index <= index == LAST_BYTE ? 3'd0 : index + 3'd1;
                {sh5, sh6, sh7} <= {sh6, sh7, data_r};
                if (index == XMAX_BYTE) begin
                    x_ok <= ordered & ({16'd0, this_value} < WIDTH);
                    in_xn <= prev_value[CBITS-1:0];
                    in_xx <= this_value[CBITS-1:0];
                end
                if (index == LAST_BYTE) begin
                    y_ok <= ordered & ({16'd0, this_value} < HEIGHT);
                    in_yn <= prev_value[CBITS-1:0];
                    in_yx <= this_value[CBITS-1:0];
                    in_dec <= decimate_r;
                end
            end
            if (~strobe_r & ready) ready <= 1'b0;
            if (loaded) begin
                set_xn <= in_xn; set_xx <= in_xx; set_yn <= in_yn; set_yx <= in_yx;
                set_dec <= in_dec;
            end
            if (check) error <= ~loaded;
            accepted <= loaded;
        end
    end

    // ---------------------------------------------------------------------------------------
    // Window logic (Fig. A1.2, Appendix B). Edge k registers the camera (FVC, LVC, first data
    // delay) and sets the X count to that pixel's column; edge k+1 registers the window test's
    // result with the pixel (CSTRB4, second data delay).
    // ---------------------------------------------------------------------------------------
    reg                  fvc = 1'b0;        // thesis FVC: frame valid synchronised
    reg                  lvc = 1'b0;        // thesis LVC: line valid synchronised
    reg                  pvc = 1'b0;        // pixel valid synchronised
    reg [PIXEL_BITS-1:0] pxc = {PIXEL_BITS{1'b0}};  // first data delay: the pixel under test
    reg                  fvd = 1'b0;        // FVC one clock later, for its transitions
    reg                  lvd = 1'b0;        // LVC one clock later
    reg      [CBITS-1:0] xcount = {CBITS{1'b0}};  // thesis X count: column of the pixel in pxc
    reg      [CBITS-1:0] ycount = {CBITS{1'b0}};  // thesis Y count: row of the line (from 0)
    reg                  start = 1'b0;      // thesis START: a valid set waits for a frame
    reg                  strben = 1'b0;     // thesis STRBEN: strobes enabled for this frame
    reg      [CBITS-1:0] xn = {CBITS{1'b0}};  // active window: minimum column (thesis XN)
    reg      [CBITS-1:0] xx = {CBITS{1'b0}};  // active window: maximum column (thesis XX)
    reg      [CBITS-1:0] yn = {CBITS{1'b0}};  // active window: minimum row (thesis YN)
    reg      [CBITS-1:0] yx = {CBITS{1'b0}};  // active window: maximum row (thesis YX)
    reg                  dec = 1'b0;        // active window is decimated
    reg                  ymin = 1'b0;       // thesis YMIN: the Y count equals ymin
    reg                  ymax = 1'b0;       // thesis YMAX: the Y count equals ymax
    reg                  xrun = 1'b0;       // columns from xmin on reached, xmax not yet passed
    reg                  yrun = 1'b0;       // rows after ymin reached, ymax not yet passed
    reg                  strobe = 1'b0;     // thesis CSTRB4
    reg [PIXEL_BITS-1:0] data = {PIXEL_BITS{1'b0}};  // second data delay: the delivered pixel
    reg                  wlast = 1'b0;      // the window's corner pixel (xmax, ymax) is in `data`
    reg                  wdone = 1'b0;      // wlast one clock later: the window is done

    wire fvlh = fvc & ~fvd;                 // thesis FVLH: a frame starts
    wire fvhl = ~fvc & fvd;                 // thesis FVHL: a frame ends
    wire lvhl = ~lvc & lvd & fvc;           // thesis LVHL: a line of the frame ends
    wire pv = fvc & lvc & pvc;              // a pixel is in pxc
    // The pending set, as it stands after the clock FVAL was first sampled, becomes the active one.
    wire arm = fvlh & start;
    wire xmin = xcount == xn;               // thesis XMIN
    wire xmax = xcount == xx;               // thesis XMAX
    wire yval = strben & (yrun | ymin);     // thesis YVAL: this line lies in the window
    wire xyval = pv & (xrun | xmin) & yval; // thesis XYVAL: the pixel in pxc lies in the window
    wire wlrst = fvhl | (lvhl & ymax & yval);  // thesis WLRST: frame or window over
    // On the 25% grid anchored at (xmin, ymin), or decimation off.
    wire decok = ~dec | ((xcount[0] == xn[0]) & (ycount[0] == yn[0]));

    always @(posedge clock) begin
        if (reset) begin
            fvc <= 1'b0; lvc <= 1'b0; pvc <= 1'b0; pxc <= {PIXEL_BITS{1'b0}};
            fvd <= 1'b0; lvd <= 1'b0;
            xcount <= {CBITS{1'b0}}; ycount <= {CBITS{1'b0}};
            start <= 1'b0; strben <= 1'b0;
            xn <= {CBITS{1'b0}}; xx <= {CBITS{1'b0}};
            yn <= {CBITS{1'b0}}; yx <= {CBITS{1'b0}}; dec <= 1'b0;
            ymin <= 1'b0; ymax <= 1'b0; xrun <= 1'b0; yrun <= 1'b0;
            strobe <= 1'b0; data <= {PIXEL_BITS{1'b0}}; wlast <= 1'b0; wdone <= 1'b0;
        end else begin
            fvc <= fval;
            lvc <= lval;
            pvc <= pixel_valid;
            pxc <= pixel;
            fvd <= fvc;
            lvd <= lvc;

            // Position counters: X advances past each pixel of the line, Y at each line end.
            if (~lvc) xcount <= {CBITS{1'b0}};
            else if (pvc & (xcount != COUNT_MAX)) xcount <= xcount + 1'b1;
            if (fvlh) ycount <= {CBITS{1'b0}};
            else if (lvhl & (ycount != COUNT_MAX)) ycount <= ycount + 1'b1;

            // Comparators and the window test.
            ymin <= ycount == yn;
            ymax <= ycount == yx;
            if (~lvc) xrun <= 1'b0;
            else if (pvc) xrun <= (xrun | xmin) & ~xmax;
            if (fvlh) yrun <= 1'b0;
            else if (lvhl) yrun <= yval & ~ymax;
            strobe <= xyval & decok;
            data <= pxc;
            // The corner pixel, whether or not decimation delivers it: after it, none is due.
            wlast <= xyval & xmax & ymax;
            wdone <= wlast;

            // START -> STRBEN -> WLRST (Appendix B); the pending set armed at FVAL rising.
            start <= loaded | (start & ~arm);
            strben <= arm | (strben & ~wlrst);
            if (arm) begin
                xn <= set_xn; xx <= set_xx; yn <= set_yn; yx <= set_yx; dec <= set_dec;
            end
        end
    end

    assign coord_ready = ready;
    assign coord_error = error;
    assign pixel_strobe = strobe;
    assign pixel_out = data;
    assign armed = start | strben;
    assign window_done = wdone;
    assign set_accepted = accepted;
endmodule

`default_nettype wire
