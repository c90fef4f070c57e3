// A function of 96 lines: scripts/dev/long-functions must report it (tests/layout).
namespace polydem::high {

// Short: braces in strings and comments do not count ("}" and // {).
int shortOne() { return sizeof("}{"); }

int tooLong(int x) {
  const auto twice = [](int v) { return 2 * v; };  // a lambda counts in its function
  x = twice(x) + 0;
  x = twice(x) + 1;
  x = twice(x) + 2;
  x = twice(x) + 3;
  x = twice(x) + 4;
  x = twice(x) + 5;
  x = twice(x) + 6;
  x = twice(x) + 7;
  x = twice(x) + 8;
  x = twice(x) + 9;
  x = twice(x) + 10;
  x = twice(x) + 11;
  x = twice(x) + 12;
  x = twice(x) + 13;
  x = twice(x) + 14;
  x = twice(x) + 15;
  x = twice(x) + 16;
  x = twice(x) + 17;
  x = twice(x) + 18;
  x = twice(x) + 19;
  x = twice(x) + 20;
  x = twice(x) + 21;
  x = twice(x) + 22;
  x = twice(x) + 23;
  x = twice(x) + 24;
  x = twice(x) + 25;
  x = twice(x) + 26;
  x = twice(x) + 27;
  x = twice(x) + 28;
  x = twice(x) + 29;
  x = twice(x) + 30;
  x = twice(x) + 31;
  x = twice(x) + 32;
  x = twice(x) + 33;
  x = twice(x) + 34;
  x = twice(x) + 35;
  x = twice(x) + 36;
  x = twice(x) + 37;
  x = twice(x) + 38;
  x = twice(x) + 39;
  x = twice(x) + 40;
  x = twice(x) + 41;
  x = twice(x) + 42;
  x = twice(x) + 43;
  x = twice(x) + 44;
  x = twice(x) + 45;
  x = twice(x) + 46;
  x = twice(x) + 47;
  x = twice(x) + 48;
  x = twice(x) + 49;
  x = twice(x) + 50;
  x = twice(x) + 51;
  x = twice(x) + 52;
  x = twice(x) + 53;
  x = twice(x) + 54;
  x = twice(x) + 55;
  x = twice(x) + 56;
  x = twice(x) + 57;
  x = twice(x) + 58;
  x = twice(x) + 59;
  x = twice(x) + 60;
  x = twice(x) + 61;
  x = twice(x) + 62;
  x = twice(x) + 63;
  x = twice(x) + 64;
  x = twice(x) + 65;
  x = twice(x) + 66;
  x = twice(x) + 67;
  x = twice(x) + 68;
  x = twice(x) + 69;
  x = twice(x) + 70;
  x = twice(x) + 71;
  x = twice(x) + 72;
  x = twice(x) + 73;
  x = twice(x) + 74;
  x = twice(x) + 75;
  x = twice(x) + 76;
  x = twice(x) + 77;
  x = twice(x) + 78;
  x = twice(x) + 79;
  x = twice(x) + 80;
  x = twice(x) + 81;
  x = twice(x) + 82;
  x = twice(x) + 83;
  x = twice(x) + 84;
  x = twice(x) + 85;
  x = twice(x) + 86;
  x = twice(x) + 87;
  x = twice(x) + 88;
  x = twice(x) + 89;
  x = twice(x) + 90;
  x = twice(x) + 91;
  return x;
}

}  // namespace polydem::high
