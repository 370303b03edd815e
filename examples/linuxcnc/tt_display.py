#!/usr/bin/python3
"""A headless LinuxCNC display: machine on, home, run one program in AUTO, print its
errors, exit (LinuxCNC shuts down when its display exits). Usage, as the INI's DISPLAY:
tt_display.py -ini FILE; the program is the INI's [DISPLAY] OPEN_FILE."""
import sys
import time
import linuxcnc

ini = linuxcnc.ini(sys.argv[sys.argv.index("-ini") + 1])
program = ini.find("DISPLAY", "OPEN_FILE")
s, c, e = linuxcnc.stat(), linuxcnc.command(), linuxcnc.error_channel()


def wait(cond, seconds):
    end = time.time() + seconds
    while time.time() < end:
        s.poll()
        err = e.poll()
        if err:
            print("tt_display: LinuxCNC error:", err[1], flush=True)
        if cond():
            return True
        time.sleep(0.02)
    return False


c.state(linuxcnc.STATE_ESTOP_RESET)
c.state(linuxcnc.STATE_ON)
ok = wait(lambda: s.task_state == linuxcnc.STATE_ON, 10)
c.home(-1)
ok = ok and wait(lambda: all(s.homed[i] for i in range(s.joints)), 30)
c.mode(linuxcnc.MODE_AUTO)
c.wait_complete()
c.program_open(program)
c.auto(linuxcnc.AUTO_RUN, 0)
wait(lambda: s.interp_state != linuxcnc.INTERP_IDLE, 5)
done = ok and wait(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.exec_state == linuxcnc.EXEC_DONE, 120)
print("tt_display: program", program, "finished" if done else "did NOT finish", flush=True)
