// DecodeTest DIR - decode, with the Java classes lcm-spy uses, the messages
// wgenc encoded with the C bindings; check the fingerprints (Java's
// LCM_FINGERPRINT against the C hash) and the field values. Exit 1 on any
// mismatch.
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.Paths;

public class DecodeTest {
    static int failures = 0;

    static void check(String what, boolean ok) {
        if (!ok) {
            System.out.println("FAIL: " + what);
            failures++;
        }
    }

    static byte[] bin(String dir, String t) throws Exception {
        return Files.readAllBytes(Paths.get(dir, t + ".bin"));
    }

    static void fingerprint(String dir, String t, long javaHash) throws Exception {
        String c = new String(Files.readAllBytes(Paths.get(dir, t + ".hash"))).trim();
        String j = String.format("%016x", javaHash);
        System.out.println(t + " fingerprint C " + c + " Java " + j);
        check(t + " fingerprint", c.equals(j));
    }

    public static void main(String[] args) throws Exception {
        String d = args[0];
        double a2 = 1.0 / 7 + 2;
        wormgear.state_t st = new wormgear.state_t(bin(d, "state_t"));
        fingerprint(d, "state_t", wormgear.state_t.LCM_FINGERPRINT);
        check("state_t", st.seq == 42 && st.n == 3 && st.xn[2] == a2 && st.fb_z2[2] == a2 && st.theta2[2] == a2);
        wormgear.poincare_t pc = new wormgear.poincare_t(bin(d, "poincare_t"));
        fingerprint(d, "poincare_t", wormgear.poincare_t.LCM_FINGERPRINT);
        check("poincare_t", pc.seq == 43 && pc.nstate == 14 && pc.y[1][13] == 1 + 13 / 3.0
                                && pc.impacts[1] == 2 && pc.period[1] == 6 && pc.nbearing == 6
                                && pc.bearing_impacts[1][3] == 3 && pc.bearing_vmax[1][5] == 0.25);
        wormgear.contact_t ct = new wormgear.contact_t(bin(d, "contact_t"));
        fingerprint(d, "contact_t", wormgear.contact_t.LCM_FINGERPRINT);
        check("contact_t", ct.seq == 44 && ct.bearing_every == 10 && ct.n == 2 && ct.kind[1] == 2 && ct.velocity[1] == 1.0 / 7 + 1);
        wormgear.status_t ss = new wormgear.status_t(bin(d, "status_t"));
        fingerprint(d, "status_t", wormgear.status_t.LCM_FINGERPRINT);
        check("status_t", ss.seq == 45 && ss.scene.equals("table3") && ss.omega == 0.7
                              && ss.regime.equals("period-1"));
        wormgear.params_t pa = new wormgear.params_t(bin(d, "params_t"));
        fingerprint(d, "params_t", wormgear.params_t.LCM_FINGERPRINT);
        check("params_t", pa.seq == 46 && pa.n == 2 && pa.name[1].equals("xi_p") && pa.value[0] == 1.3
                              && pa.steps_per_period == 128);
        wormgear.cmd_t cmd = new wormgear.cmd_t(bin(d, "cmd_t"));
        fingerprint(d, "cmd_t", wormgear.cmd_t.LCM_FINGERPRINT);
        check("cmd_t", cmd.seq == 47 && cmd.op.equals("set") && cmd.names[0].equals("omega")
                           && cmd.values[0] == 1.3);
        wormgear.ack_t ack = new wormgear.ack_t(bin(d, "ack_t"));
        fingerprint(d, "ack_t", wormgear.ack_t.LCM_FINGERPRINT);
        check("ack_t", ack.seq == 48 && ack.cmd_seq == 47 && ack.code.equals("ERANGE") && ack.status == -2);
        wormgear.tick_t tk = new wormgear.tick_t(bin(d, "tick_t"));
        fingerprint(d, "tick_t", wormgear.tick_t.LCM_FINGERPRINT);
        check("tick_t", tk.seq == 49 && tk.nsteps == 5);
        wormgear.scope_t sc = new wormgear.scope_t(bin(d, "scope_t"));
        fingerprint(d, "scope_t", wormgear.scope_t.LCM_FINGERPRINT);
        check("scope_t", sc.seq == 50 && sc.xn == 1.2154 && sc.omega == 1.2 && sc.force == 0.41);
        System.out.println(failures == 0 ? "all 9 types decode" : failures + " failures");
        System.exit(failures == 0 ? 0 : 1);
    }
}
