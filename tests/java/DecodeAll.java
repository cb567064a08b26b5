// Decodes every event of an LCM log through the Java bindings of the mtg types, as lcm-spy does:
// the first 8 bytes name the type (its LCM fingerprint), the class decodes the rest. Fails when an
// event matches no class, a decode throws, or a type of the jar has no event in the log.
// Usage: java -cp lcm.jar:mtg_lcmtypes.jar:. DecodeAll <log> <mtg_lcmtypes.jar>

import java.io.ByteArrayInputStream;
import java.io.DataInputStream;
import java.io.EOFException;
import java.util.Enumeration;
import java.util.HashMap;
import java.util.Map;
import java.util.Set;
import java.util.TreeSet;
import java.util.jar.JarEntry;
import java.util.jar.JarFile;
import lcm.logging.Log;

public class DecodeAll {
  public static void main(String[] args) throws Exception {
    Map<Long, Class<?>> byFingerprint = new HashMap<>();
    try (JarFile jar = new JarFile(args[1])) {
      for (Enumeration<JarEntry> e = jar.entries(); e.hasMoreElements();) {
        String name = e.nextElement().getName();
        if (!name.startsWith("mtg/") || !name.endsWith(".class") || name.contains("$")) continue;
        Class<?> c = Class.forName(name.substring(0, name.length() - 6).replace('/', '.'));
        byFingerprint.put(c.getField("LCM_FINGERPRINT").getLong(null), c);
      }
    }
    Set<String> decoded = new TreeSet<>();
    Log log = new Log(args[0], "r");
    while (true) {
      Log.Event ev;
      try {
        ev = log.readNext();
      } catch (EOFException end) {
        break;
      }
      long fingerprint = new DataInputStream(new ByteArrayInputStream(ev.data)).readLong();
      Class<?> c = byFingerprint.get(fingerprint);
      if (c == null) {
        System.out.println("UNKNOWN type on " + ev.channel);
        System.exit(1);
      }
      Object msg = c.getConstructor(byte[].class).newInstance((Object) ev.data);
      String run = "-";
      try {
        Object header = c.getField("header").get(msg);
        run = (String) header.getClass().getField("run_id").get(header);
      } catch (NoSuchFieldException noHeader) {
        // a nested type (header_t, task_t, image_t, ...) recorded on its own
      }
      System.out.println("DECODED " + c.getSimpleName() + " " + ev.channel + " run=" + run);
      decoded.add(c.getSimpleName());
    }
    Set<String> missing = new TreeSet<>();
    for (Class<?> c : byFingerprint.values()) {
      if (!decoded.contains(c.getSimpleName())) missing.add(c.getSimpleName());
    }
    if (!missing.isEmpty()) {
      System.out.println("MISSING " + missing);
      System.exit(1);
    }
    System.out.println("ALL " + decoded.size() + " types decoded");
  }
}
