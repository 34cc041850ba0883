<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" name="keyed" tilewidth="3" tileheight="2" spacing="2" margin="1" tilecount="4" columns="2">
 <image source="tiles.png" trans="ff00ff" width="12" height="12"/>
 <tile id="2"><animation><frame tileid="1" duration="50"/></animation></tile>
</tileset>
