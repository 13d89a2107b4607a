"""The kept read and the write of a change as one Perl process on the robot, where it has Perl.

``scripts_apply.READ_KEPT`` is a shell script that starts ``sh`` and then seven programs for a
one-file change (tar to read, head and tar to unpack, sync, sha256sum, mv, sync). Every robot
of a fleet runs it at once, and each program costs the robot about a millisecond of CPU. Perl
is part of every Debian and Ubuntu system (``perl-base`` is essential, and so on the Panther's
built-in computer), and one ``perl`` process does the same in about a third of that: it reads
the file itself, unpacks the same tar archive from the same input, writes each file with
``O_SYNC`` (each write returns once the data and the inode are on disk, as ``fsync`` does),
compares the file with the backup copy of what the plan read instead of hashing it, renames,
and fsyncs the directories of the renamed files itself (the ``fsync`` system call by its
number, known per machine type of the ``perl`` binary: x86-64, i386, ARM, AArch64, RISC-V;
elsewhere it runs ``sync`` on them).

Same arguments, input, output, exit codes and effects as the shell script (see there); the
command runs the shell script where ``perl`` is missing, or not on Linux (the numeric ``open``
flags are Linux's). Only core Perl is used and no module is loaded, not even ``strict`` (the
tests compile the program with ``-Mstrict -w``): ``IO::Handle`` or ``Fcntl`` would cost more
than the programs saved, ``strict.pm`` alone half a millisecond per robot.

Nothing user-given is part of the code: paths and values arrive in ``@ARGV`` and on stdin.
"""

from __future__ import annotations

import os

from panther_ops.transport.base import Command
from panther_ops.transport.scripts_apply import APPLY, READ_KEPT

_PRELUDE = r"""
$| = 1;
my $sh = shift @ARGV; exec('sh', '-c', $sh, 'sh', @ARGV) if $^O ne 'linux';
$SIG{HUP} = $SIG{PIPE} = 'IGNORE';
my $O_W = 01 | 0100 | 01000 | 04010000;  # O_WRONLY|O_CREAT|O_TRUNC|O_SYNC (Linux)
sub norm { my $x = shift; $x =~ s{/+}{/}g; $x =~ s{(.)/$}{$1}; $x }
sub up { my $x = shift; $x =~ s{/[^/]*$}{}; $x }
my $r = $ENV{PANTHER_OPS_ROOT} // ''; my $home = $ENV{HOME} // '';
sub fail { my ($code, $msg) = @_; print STDERR $msg, "\n"; exit $code }
sub oct0 { my ($v, $n) = @_; sprintf("%0*o", $n - 1, $v) . "\0" }
"""

_READ = r"""
my ($p, $mark) = @ARGV; $p = "$home/" . substr($p, 2) if substr($p, 0, 2) eq '~/';
my $f = "$r$p";
print "$home\n";
fail(44, "no such file: $p") unless -f $f;
open(my $in, '<:raw', $f) or fail(1, "cannot read $p: $!");
my @st = stat($in); my $data = do { local $/; <$in> } // ''; close $in;
my $h = pack('a100 a8 a8 a8 a12 a12 a8 a1 a100 a6 a2 a32 a32 a8 a8 a155 a12', 'f',
  oct0($st[2] & 07777, 8), oct0(0, 8), oct0(0, 8), oct0(length $data, 12), oct0($st[9], 12), ' ' x 8,
  '0', '', "ustar\0", '00', '', '', '', '', '', '');
substr($h, 148, 8) = sprintf("%06o\0 ", unpack('%32C*', $h));
print $h, $data, "\0" x ((512 - length($data) % 512) % 512), "\0" x 1024, "$mark\n";
sub line { my $l = <STDIN>; exit 0 unless defined $l; chomp $l; $l }
exit 0 unless line() eq 'apply';
my $n = line(); my @a = map { line() } 1 .. $n;
"""

_APPLY = r"""
my ($w, $status, $size, $val) = splice(@a, 0, 4); $w = norm("$r$w");
my (@e, %body, %mode);
while (@a) {
  my ($path, $want, $t, $ref) = splice(@a, 0, 4);
  push @e, [$path, norm("$r$path"), $want, $t eq '-' ? '-' : norm("$r$t"), $ref];
}
sub drop { for (@e) { unlink $_->[3] if $_->[3] ne '-' } }
sub rmtree {
  my $d = shift; return unlink $d if !-d $d || -l $d;
  opendir(my $dh, $d) or return; my @k = grep { !/^\.\.?$/ } readdir $dh; closedir $dh;
  rmtree("$d/$_") for @k; rmdir $d;
}
sub unmake { drop(); rmtree($w); rmdir up($w); rmdir up(up($w)) }
sub bad { unmake(); fail(1, "cannot unpack the upload" . (@_ ? ": @_" : '')) }
sub mkpath { my $d = shift; return if $d eq '' || -d $d; mkpath(up($d)); mkdir $d }
sub status { open(my $s, '>', "$w/status") or return; print $s @_, "\n"; close $s }
sub syncdirs {
  my @d = @_; my ($nr, $x, $elf, $dh);
  if (open($x, '<:raw', '/proc/self/exe') && read($x, $elf, 20) == 20) {
    $nr = {62 => 74, 3 => 118, 40 => 118, 183 => 82, 243 => 82}->{unpack('v', substr($elf, 18, 2))}
      if substr($elf, 0, 4) eq "\x7fELF" && ord(substr($elf, 5, 1)) == 1;  # fsync by machine
  }
  @d = grep { !(defined $nr && sysopen($dh, $_, 0) && syscall($nr, fileno($dh)) == 0) } @d;
  return unless @d;
  my $pid = fork; if (defined $pid && !$pid) { open(STDERR, '>', '/dev/null'); exec('sync', '--', @d); exit 127 }
  waitpid($pid, 0) if $pid;
}
my $buf = '';
while (length($buf) < $size) { read(STDIN, $buf, $size - length($buf), length $buf) or bad() }
for my $i (0 .. $#e) {
  my $x = $e[$i]; next unless $x->[4] eq '1' && -e $x->[1];
  my $m = (stat $x->[1])[2] & 07777; $mode{$x->[3]} = $m if $x->[3] ne '-'; $mode{"$w/files/$i"} = $m;
}
my ($pos, $long) = (0, undef);
while ($pos + 512 <= length $buf) {
  my $hd = substr($buf, $pos, 512); last if $hd =~ /^\0*$/;
  my ($name, $m, $sz, $mt, $type) = unpack('Z100 A8 x8 x8 A12 A12 x8 a1', $hd);
  ($m, $sz, $mt) = map { oct($_ =~ s/[\0 ]//gr || '0') } ($m, $sz, $mt);
  my $body = substr($buf, $pos + 512, $sz); $pos += 512 + 512 * int(($sz + 511) / 512);
  if ($type eq 'L') { ($long = $body) =~ s/\0.*//s; next }
  $name = $long if defined $long; $long = undef;
  my $to = norm("$r/$name"); mkpath(up($to));
  if ($type eq '5') {
    next if -d $to;
    my $old = umask 0; my $ok = mkdir($to, $m); umask $old; $ok or bad("$to: $!"); next;
  }
  bad($name) unless $type eq '0' || $type eq "\0";
  my $fm = $mode{$to} // $m; $body{$to} = $body;
  my $old = umask 0; my $ok = sysopen(my $o, $to, $O_W, $fm); umask $old; $ok or bad("$to: $!");
  for (my $off = 0; $off < length $body;) { $off += syswrite($o, $body, length($body) - $off, $off) || bad("$to: $!") }
  close($o) or bad("$to: $!"); chmod $fm, $to; utime $mt, $mt, $to;
}
my $vt = $val ne '-' && $val < @e ? $e[$val][3] : '-';
if ($vt ne '-' && $r eq ''
    && system('sh', '-c', 'command -v docker >/dev/null 2>&1 && docker compose version >/dev/null 2>&1') == 0) {
  open(my $dc, '-|', 'sh', '-c', 'cd "$1" && docker compose -f "$2" config -q 2>&1', 'sh', up($vt), $vt)
    or fail(1, "cannot run docker compose");
  my $err = do { local $/; <$dc> } // ''; close $dc;
  if ($?) { chomp $err; drop(); status("refused: $err"); fail(5, $err) }
}
print "\@\@staged\n";
my $go = <STDIN> // ''; chomp $go;
if ($go eq 'stop') { unmake(); exit 4 }
if ($go ne 'go') { drop(); status("abandoned: no go-ahead (" . ($go eq '' ? 'connection closed' : $go) . ")"); exit 4 }
for my $i (0 .. $#e) {
  my $x = $e[$i];
  if ($x->[2] eq '-') {
    next unless -e $x->[1];
    print STDERR "$x->[0] appeared on the robot since it was read\n"; unmake(); exit 3;
  }
  my ($now, $was) = (undef, $body{"$w/files/$i"});
  if (open(my $c, '<:raw', $x->[1])) { local $/; $now = <$c> // ''; close $c }
  next if defined $now && defined $was && $now eq $was;
  print STDERR "$x->[0] changed on the robot since it was read\n"; unmake(); exit 3;
}
my @dirs;
for my $x (@e) {
  if ($x->[3] eq '-') { unlink $x->[1]; exit 1 if -e $x->[1] } else { rename($x->[3], $x->[1]) or exit 1 }
  push @dirs, up($x->[1]);
}
syncdirs(@dirs);
status($status) if $status ne '';
exit 0;
"""

READ_KEPT_PERL = _PRELUDE + _READ + _APPLY
"""``scripts_apply.READ_KEPT`` in Perl."""

APPLY_PERL = _PRELUDE + "my @a = @ARGV;\n" + _APPLY
"""``scripts_apply.APPLY`` in Perl."""



def enabled() -> bool:
    """Whether commands offer the robot the Perl variant (``PANTHER_OPS_ROBOT_PERL=0``: never)."""
    return os.environ.get("PANTHER_OPS_ROBOT_PERL", "1") != "0"


def read_kept(path: str, mark: str) -> Command:
    """The kept read of ``path`` (then the write): Perl where the robot has it, else the shell."""
    return Command.sh(READ_KEPT, path, mark, perl=READ_KEPT_PERL if enabled() else None)


def apply(argv: list[str]) -> Command:
    """The write alone (no kept read to carry it): Perl where the robot has it, else the shell."""
    return Command.sh(APPLY, *argv, perl=APPLY_PERL if enabled() else None)
