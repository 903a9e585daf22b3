%
(Circular test: XY plane, radius 35 mm, feed 5000 mm/min, centre X0 Y0,)
(first counter-clockwise, then clockwise.)
(Each circle starts at rest at the centre. A feed-in semicircle of radius 17.5 mm)
(turning the same way as the circle meets it tangentially at quadrant point A)
(X35 Y0; then one full circle; then a feed-out semicircle of radius 17.5 mm leads)
(tangentially back to the centre, where the axes come to rest. The centre words)
(I and J are relative to the start of each block.)
G21 G17 G90                 (millimetres, XY plane, absolute coordinates)
G0 X0 Y0                    (start at the centre)

(counter-clockwise: A -> B -> C -> D -> A)
G3 X35 Y0 I17.5 J0 F5000    (feed-in, through X17.5 Y-17.5)
G3 X35 Y0 I-35 J0           (full circle about X0 Y0)
G3 X0 Y0 I-17.5 J0          (feed-out, through X17.5 Y17.5, back to the centre)

(clockwise: A -> D -> C -> B -> A; the reversal at the centre is an exact stop)
G2 X35 Y0 I17.5 J0          (feed-in, through X17.5 Y17.5)
G2 X35 Y0 I-35 J0           (full circle about X0 Y0)
G2 X0 Y0 I-17.5 J0          (feed-out, through X17.5 Y-17.5, back to the centre)
M30
%
