// SpyCheck SECONDS LCM_URL [SECONDS2] - run lcm-spy (lcm.spy.Spy) in this
// JVM on a display (Xvfb in the tests), wait, then read its channel table
// from the Swing component tree and print one line per row: channel, type,
// and the message count. With SECONDS2, "round 0 done" after the table,
// then the table again SECONDS2 later (a test sends hostile datagrams in
// between). Exit 0 if the table was found.
import java.awt.Component;
import java.awt.Container;
import java.awt.Frame;
import javax.swing.JTable;
import javax.swing.SwingUtilities;

public class SpyCheck {
    static JTable find(Component c) {
        if (c instanceof JTable)
            return (JTable) c;
        if (c instanceof Container)
            for (Component k : ((Container) c).getComponents()) {
                JTable t = find(k);
                if (t != null)
                    return t;
            }
        return null;
    }

    public static void main(String[] args) throws Exception {
        lcm.spy.Spy.main(new String[] {"--lcm-url=" + args[1]});
        Thread.sleep((long) (Double.parseDouble(args[0]) * 1000));
        final int[] rows = {-1};
        if (args.length > 2) {
            table(rows);
            System.out.println("round 0 done");
            System.out.flush();
            Thread.sleep((long) (Double.parseDouble(args[2]) * 1000));
        }
        table(rows);
        System.exit(rows[0] >= 0 ? 0 : 1);
    }

    static void table(final int[] rows) throws Exception {
        SwingUtilities.invokeAndWait(() -> {
            for (Frame f : Frame.getFrames()) {
                JTable t = find(f);
                if (t == null)
                    continue;
                StringBuilder h = new StringBuilder("columns:");
                for (int c = 0; c < t.getColumnCount(); c++)
                    h.append(" | ").append(t.getColumnName(c));
                System.out.println(h);
                rows[0] = t.getRowCount();
                for (int r = 0; r < t.getRowCount(); r++) {
                    StringBuilder s = new StringBuilder("row:");
                    for (int c = 0; c < t.getColumnCount(); c++)
                        s.append(" | ").append(t.getValueAt(r, c));
                    System.out.println(s);
                }
            }
        });
    }
}
