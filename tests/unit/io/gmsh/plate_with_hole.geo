SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Disk(2) = {0.5, 0.5, 0, 0.2};
BooleanDifference(3) = {Surface{1}; Delete;}{Surface{2}; Delete;};
b() = Boundary{Surface{3};};
Physical Curve("outer_dirichlet") = {b(0), b(1), b(2), b(3)};
Physical Curve("hole_neumann") = {b(4)};
Physical Surface("domain") = {3};
Mesh.CharacteristicLengthMax = 0.2;
