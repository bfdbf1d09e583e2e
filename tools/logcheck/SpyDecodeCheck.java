/* SpyDecodeCheck: decodes every event of an lcm-logger file the way
 * lcm-spy does (lcm.spy.Spy.MySubscriber: the type from the fingerprint
 * through lcm.spy.LCMTypeDatabase, which scans the classpath, then the
 * type's DataInput constructor), re-encodes it and checks the bytes are
 * the event's own, followed by nothing or by one authentication trailer
 * (src/daemons/common/auth.h). Prints the events decoded per type; exit 1 if
 * any event fails.
 *   java -cp /usr/share/java/lcm.jar:build/lib/tandem_types.jar:DIR SpyDecodeCheck LOG
 */
import java.io.ByteArrayOutputStream;
import java.io.DataInput;
import java.io.DataOutputStream;
import java.io.EOFException;
import java.util.Arrays;
import java.util.Map;
import java.util.TreeMap;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMEncodable;
import lcm.logging.Log;
import lcm.spy.LCMTypeDatabase;

public class SpyDecodeCheck {
    /* auth.h: the trailer's fixed part, and one tag per receiver before it */
    static final int FIXED_BYTES = 40, TAG_BYTES = 21;

    /* 1 when data ends in exactly rest bytes of one v2 trailer. */
    static boolean isTrailer(byte[] data, int rest) {
        if (rest < FIXED_BYTES)
            return false;
        int f = data.length - FIXED_BYTES;
        int tags = data[f + 38] & 0xff;
        return data[f] == 'T' && data[f + 1] == 'A' && data[f + 2] == 2 && data[f + 39] == 0
            && rest == FIXED_BYTES + tags * TAG_BYTES;
    }

    public static void main(String[] args) throws Exception {
        LCMTypeDatabase types = new LCMTypeDatabase();
        Log log = new Log(args[0], "r");
        Map<String, Integer> decoded = new TreeMap<>();
        int events = 0, bad = 0, signed = 0;
        for (;;) {
            Log.Event ev;
            try {
                ev = log.readNext();
            } catch (EOFException e) {
                break;
            }
            if (ev.channel.equals("LCM_SELF_TEST"))
                continue;   /* LCM's own start-up probe, not a tandem message */
            events++;
            try {
                LCMDataInputStream ins = new LCMDataInputStream(ev.data, 0, ev.data.length);
                long fingerprint = ins.readLong();
                ins.reset();
                Class<?> cls = types.getClassByFingerprint(fingerprint);
                if (cls == null)
                    throw new Exception("no type with this fingerprint");
                Object o = cls.getConstructor(DataInput.class).newInstance(ins);
                ByteArrayOutputStream bytes = new ByteArrayOutputStream();
                ((LCMEncodable) o).encode(new DataOutputStream(bytes));
                byte[] enc = bytes.toByteArray();
                int rest = ev.data.length - enc.length;
                if ((rest != 0 && !isTrailer(ev.data, rest)) || !Arrays.equals(enc, Arrays.copyOf(ev.data, enc.length)))
                    throw new Exception("re-encoding gives other bytes (" + rest + " bytes left)");
                signed += rest != 0 ? 1 : 0;
                decoded.merge(cls.getSimpleName(), 1, Integer::sum);
            } catch (Exception e) {
                if (bad++ < 10)
                    System.out.println("lcm-spy decode FAILED: " + ev.channel + ": " + e);
            }
        }
        log.close();
        System.out.println("lcm-spy decoding: " + events + " events, " + signed + " with a trailer, "
                           + decoded.size() + " types, failed " + bad + ": " + decoded);
        System.exit(bad == 0 && events > 0 ? 0 : 1);
    }
}
