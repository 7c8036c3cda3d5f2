// SPDX-License-Identifier: MIT
// A fixture for check_function_length.py: a firmware function of 81 lines.

int tick_everything(int x) {
  x += 0;   // one line of the body
  x += 1;   // one line of the body
  x += 2;   // one line of the body
  x += 3;   // one line of the body
  x += 4;   // one line of the body
  x += 5;   // one line of the body
  x += 6;   // one line of the body
  x += 7;   // one line of the body
  x += 8;   // one line of the body
  x += 9;   // one line of the body
  x += 10;  // one line of the body
  x += 11;  // one line of the body
  x += 12;  // one line of the body
  x += 13;  // one line of the body
  x += 14;  // one line of the body
  x += 15;  // one line of the body
  x += 16;  // one line of the body
  x += 17;  // one line of the body
  x += 18;  // one line of the body
  x += 19;  // one line of the body
  x += 20;  // one line of the body
  x += 21;  // one line of the body
  x += 22;  // one line of the body
  x += 23;  // one line of the body
  x += 24;  // one line of the body
  x += 25;  // one line of the body
  x += 26;  // one line of the body
  x += 27;  // one line of the body
  x += 28;  // one line of the body
  x += 29;  // one line of the body
  x += 30;  // one line of the body
  x += 31;  // one line of the body
  x += 32;  // one line of the body
  x += 33;  // one line of the body
  x += 34;  // one line of the body
  x += 35;  // one line of the body
  x += 36;  // one line of the body
  x += 37;  // one line of the body
  x += 38;  // one line of the body
  x += 39;  // one line of the body
  x += 40;  // one line of the body
  x += 41;  // one line of the body
  x += 42;  // one line of the body
  x += 43;  // one line of the body
  x += 44;  // one line of the body
  x += 45;  // one line of the body
  x += 46;  // one line of the body
  x += 47;  // one line of the body
  x += 48;  // one line of the body
  x += 49;  // one line of the body
  x += 50;  // one line of the body
  x += 51;  // one line of the body
  x += 52;  // one line of the body
  x += 53;  // one line of the body
  x += 54;  // one line of the body
  x += 55;  // one line of the body
  x += 56;  // one line of the body
  x += 57;  // one line of the body
  x += 58;  // one line of the body
  x += 59;  // one line of the body
  x += 60;  // one line of the body
  x += 61;  // one line of the body
  x += 62;  // one line of the body
  x += 63;  // one line of the body
  x += 64;  // one line of the body
  x += 65;  // one line of the body
  x += 66;  // one line of the body
  x += 67;  // one line of the body
  x += 68;  // one line of the body
  x += 69;  // one line of the body
  x += 70;  // one line of the body
  x += 71;  // one line of the body
  x += 72;  // one line of the body
  x += 73;  // one line of the body
  x += 74;  // one line of the body
  x += 75;  // one line of the body
  x += 76;  // one line of the body
  x += 77;  // one line of the body
  x += 78;  // one line of the body
  x += 79;  // one line of the body
  x += 80;  // one line of the body
}

// Not a function: a table, and a function of exactly 80 lines below.
// clang-format off
const int kTable[] = {
    0,
    1,
    2,
    3,
    4,
    5,
    6,
    7,
    8,
    9,
    10,
    11,
    12,
    13,
    14,
    15,
    16,
    17,
    18,
    19,
    20,
    21,
    22,
    23,
    24,
    25,
    26,
    27,
    28,
    29,
    30,
    31,
    32,
    33,
    34,
    35,
    36,
    37,
    38,
    39,
    40,
    41,
    42,
    43,
    44,
    45,
    46,
    47,
    48,
    49,
    50,
    51,
    52,
    53,
    54,
    55,
    56,
    57,
    58,
    59,
    60,
    61,
    62,
    63,
    64,
    65,
    66,
    67,
    68,
    69,
    70,
    71,
    72,
    73,
    74,
    75,
    76,
    77,
    78,
    79,
    80,
    81,
    82,
    83,
    84,
    85,
    86,
    87,
    88,
    89,
};
// clang-format on

int eighty_lines(int x) {
  x -= 0;
  x -= 1;
  x -= 2;
  x -= 3;
  x -= 4;
  x -= 5;
  x -= 6;
  x -= 7;
  x -= 8;
  x -= 9;
  x -= 10;
  x -= 11;
  x -= 12;
  x -= 13;
  x -= 14;
  x -= 15;
  x -= 16;
  x -= 17;
  x -= 18;
  x -= 19;
  x -= 20;
  x -= 21;
  x -= 22;
  x -= 23;
  x -= 24;
  x -= 25;
  x -= 26;
  x -= 27;
  x -= 28;
  x -= 29;
  x -= 30;
  x -= 31;
  x -= 32;
  x -= 33;
  x -= 34;
  x -= 35;
  x -= 36;
  x -= 37;
  x -= 38;
  x -= 39;
  x -= 40;
  x -= 41;
  x -= 42;
  x -= 43;
  x -= 44;
  x -= 45;
  x -= 46;
  x -= 47;
  x -= 48;
  x -= 49;
  x -= 50;
  x -= 51;
  x -= 52;
  x -= 53;
  x -= 54;
  x -= 55;
  x -= 56;
  x -= 57;
  x -= 58;
  x -= 59;
  x -= 60;
  x -= 61;
  x -= 62;
  x -= 63;
  x -= 64;
  x -= 65;
  x -= 66;
  x -= 67;
  x -= 68;
  x -= 69;
  x -= 70;
  x -= 71;
  x -= 72;
  x -= 73;
  x -= 74;
  x -= 75;
  x -= 76;
  x -= 77;
  x -= 78;
  x -= 79;
}
