`timescale 1ns/1ps
// Replays a stimulus recorded from the rust-hdl simulation into the exported window_unit, one
// hex word per pixel clock: {decimate, coord_data[7:0], coord_strobe, pixel[7:0], lval, fval}.
// After each rising edge it writes the outputs as one hex word:
// {coord_error, pixel_out[7:0], pixel_strobe, coord_ready}.
// Usage: vvp replay.vvp +stim=IN.hex +out=OUT.hex
module replay_tb;
  reg clock = 0;
  reg fval = 0, lval = 0, coord_strobe = 0, decimate = 0;
  reg [7:0] pixel = 0, coord_data = 0;
  wire coord_ready, pixel_strobe, coord_error;
  wire [7:0] pixel_out;
  reg [19:0] word;
  integer fin, fout;
  reg [8*1024-1:0] stim_path, out_path;

  window_unit dut(.clock(clock), .fval(fval), .lval(lval), .pixel(pixel),
                  .coord_strobe(coord_strobe), .coord_data(coord_data),
                  .coord_ready(coord_ready), .decimate(decimate),
                  .pixel_strobe(pixel_strobe), .pixel_out(pixel_out),
                  .coord_error(coord_error));

  initial begin
    if (!$value$plusargs("stim=%s", stim_path) || !$value$plusargs("out=%s", out_path)) begin
      $display("replay_tb: usage: +stim=IN.hex +out=OUT.hex");
      $finish;
    end
    fin = $fopen(stim_path, "r");
    fout = $fopen(out_path, "w");
    if (fin == 0 || fout == 0) begin
      $display("replay_tb: cannot open %0s or %0s", stim_path, out_path);
      $finish;
    end
    while ($fscanf(fin, "%h\n", word) == 1) begin
      {decimate, coord_data, coord_strobe, pixel, lval, fval} = word;
      #5 clock = 1;
      #1 $fwrite(fout, "%h\n", {coord_error, pixel_out, pixel_strobe, coord_ready});
      #4 clock = 0;
    end
    $fclose(fout);
    $finish;
  end
endmodule
