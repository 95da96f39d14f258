// Test top of the cocotb bench of window_unit_axis (hdl/cocotb/test_window_unit_axis.py):
// three windows, each output under its own prefix m<k>_axis_ so that cocotbext-axi's
// AxiStreamSink can bind to it. Everything else passes straight through.
`default_nettype none

module tb_window_unit_axis #(
    parameter integer WIDTH = 80,
    parameter integer HEIGHT = 40,
    parameter integer PIXEL_BITS = 16,
    parameter integer FIFO_DEPTH = 8
) (
    input  wire                            aclk,
    input  wire                            aresetn,
    input  wire [((PIXEL_BITS+7)/8)*8-1:0] s_axis_tdata,
    input  wire                            s_axis_tvalid,
    output wire                            s_axis_tready,
    input  wire                            s_axis_tuser,
    input  wire                            s_axis_tlast,
    output wire [((PIXEL_BITS+7)/8)*8-1:0] m0_axis_tdata, m1_axis_tdata, m2_axis_tdata,
    output wire                            m0_axis_tvalid, m1_axis_tvalid, m2_axis_tvalid,
    input  wire                            m0_axis_tready, m1_axis_tready, m2_axis_tready,
    output wire                            m0_axis_tuser, m1_axis_tuser, m2_axis_tuser,
    output wire                            m0_axis_tlast, m1_axis_tlast, m2_axis_tlast,
    input  wire [11:0]                     s_axil_awaddr,
    input  wire [2:0]                      s_axil_awprot,   // unused: cocotbext-axi drives it
    input  wire                            s_axil_awvalid,
    output wire                            s_axil_awready,
    input  wire [31:0]                     s_axil_wdata,
    input  wire [3:0]                      s_axil_wstrb,
    input  wire                            s_axil_wvalid,
    output wire                            s_axil_wready,
    output wire [1:0]                      s_axil_bresp,
    output wire                            s_axil_bvalid,
    input  wire                            s_axil_bready,
    input  wire [11:0]                     s_axil_araddr,
    input  wire [2:0]                      s_axil_arprot,   // unused
    input  wire                            s_axil_arvalid,
    output wire                            s_axil_arready,
    output wire [31:0]                     s_axil_rdata,
    output wire [1:0]                      s_axil_rresp,
    output wire                            s_axil_rvalid,
    input  wire                            s_axil_rready,
    output wire                            irq
);
    window_unit_axis #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS), .WINDOWS(3),
                       .FIFO_DEPTH(FIFO_DEPTH)) dut (
        .aclk(aclk), .aresetn(aresetn),
        .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
        .s_axis_tuser(s_axis_tuser), .s_axis_tlast(s_axis_tlast),
        .m_axis_tdata({m2_axis_tdata, m1_axis_tdata, m0_axis_tdata}),
        .m_axis_tvalid({m2_axis_tvalid, m1_axis_tvalid, m0_axis_tvalid}),
        .m_axis_tready({m2_axis_tready, m1_axis_tready, m0_axis_tready}),
        .m_axis_tuser({m2_axis_tuser, m1_axis_tuser, m0_axis_tuser}),
        .m_axis_tlast({m2_axis_tlast, m1_axis_tlast, m0_axis_tlast}),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(s_axil_araddr), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready), .irq(irq));
endmodule

`default_nettype wire
